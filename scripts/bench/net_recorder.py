#!/usr/bin/python3
"""Bytes on the split's topics over time (benchmark suite, network section).

python3 -m bench.net_recorder --out net.csv [--ns /edge_slam] [--topics keyframes frames map_updates]

Subscribes to each topic with rospy.AnyMsg, so nothing is deserialised: the size logged is the
serialized message as it crossed the wire (without the 4-byte TCPROS length prefix). Waits for
the ROS master to appear, so it can be started before roslaunch; stops on SIGINT/SIGTERM.
Rows: wall time, topic, bytes.
"""
import argparse
import time

import rospy

from .recorder_node import run_recorder


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--ns", default="/edge_slam")
    ap.add_argument("--topics", nargs="+", default=["keyframes", "frames", "map_updates"])
    ap.add_argument("--master-timeout", type=float, default=120.0)
    args = ap.parse_args(rospy.myargv()[1:])
    files = []

    def subscribe():
        out = open(args.out, "w", buffering=1)
        out.write("t,topic,bytes\n")
        files.append(out)

        def record(topic):
            def callback(msg):
                out.write(f"{time.time():.3f},{topic},{len(msg._buff)}\n")
            return callback

        for topic in args.topics:
            rospy.Subscriber(f"{args.ns.rstrip('/')}/{topic}", rospy.AnyMsg, record(topic), queue_size=1000,
                             buff_size=64 << 20)

    run_recorder("bench_net_recorder", subscribe, args.master_timeout)
    for f in files:
        f.flush()
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
