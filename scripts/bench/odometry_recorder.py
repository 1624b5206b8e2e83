#!/usr/bin/python3
"""The mobile's tracked poses as a TUM trajectory, from its nav_msgs/Odometry topic.

python3 -m bench.odometry_recorder --out trajectory.txt [--topic /edge_slam/mobile/odometry]

Used where the benchmark launches mobile and edge itself (bandwidth-limit runs in network
namespaces) instead of going through scripts/eval.sh. One line per message: the image stamp
and the pose of the camera in the map frame. Waits for the master; stops on SIGINT/SIGTERM.
"""
import argparse

import rospy
from nav_msgs.msg import Odometry

from .recorder_node import run_recorder


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--topic", default="/edge_slam/mobile/odometry")
    args = ap.parse_args(rospy.myargv()[1:])
    files = []

    def subscribe():
        out = open(args.out, "w", buffering=1)
        out.write("# timestamp tx ty tz qx qy qz qw (mobile odometry)\n")
        files.append(out)

        def on_odometry(msg):
            p, q = msg.pose.pose.position, msg.pose.pose.orientation
            out.write(f"{msg.header.stamp.to_sec():.6f} {p.x:.6f} {p.y:.6f} {p.z:.6f} "
                      f"{q.x:.6f} {q.y:.6f} {q.z:.6f} {q.w:.6f}\n")

        rospy.Subscriber(args.topic, Odometry, on_odometry, queue_size=100)

    run_recorder("bench_odometry_recorder", subscribe)
    for f in files:
        f.flush()
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
