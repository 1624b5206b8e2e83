#!/usr/bin/python3
"""The mobile's tracked poses as a TUM trajectory, from its nav_msgs/Odometry topic.

odometry_recorder.py --out trajectory.txt [--topic /edge_slam/mobile/odometry]

Used where the benchmark launches mobile and edge itself (bandwidth-limit runs in network
namespaces) instead of going through scripts/eval.sh. One line per message: the image stamp
and the pose of the camera in the map frame. Waits for the master; stops on SIGINT/SIGTERM.
"""
import argparse
import signal
import sys
import time

import rosgraph
import rospy
from nav_msgs.msg import Odometry


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--topic", default="/edge_slam/mobile/odometry")
    args = ap.parse_args(rospy.myargv()[1:])
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    deadline = time.monotonic() + 120
    while not rosgraph.is_master_online():
        if stop or time.monotonic() > deadline:
            sys.exit("odometry_recorder: no ROS master")
        time.sleep(0.2)
    out = open(args.out, "w", buffering=1)
    out.write("# timestamp tx ty tz qx qy qz qw (mobile odometry)\n")

    def on_odometry(msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        out.write(f"{msg.header.stamp.to_sec():.6f} {p.x:.6f} {p.y:.6f} {p.z:.6f} "
                  f"{q.x:.6f} {q.y:.6f} {q.z:.6f} {q.w:.6f}\n")

    rospy.init_node("bench_odometry_recorder", anonymous=True, disable_signals=True)
    rospy.Subscriber(args.topic, Odometry, on_odometry, queue_size=100)
    while not stop and rosgraph.is_master_online():
        time.sleep(0.2)
    out.flush()
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
