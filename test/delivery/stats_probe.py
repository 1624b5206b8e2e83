#!/usr/bin/python3
"""Writes every edge_slam_msgs/Stats message of the mobile as one JSON line {"wall": t, name: value}
(line-buffered), for the delivery tests. stats_probe.py --out stats.jsonl; stops on SIGINT/SIGTERM."""
import json
import os
import sys
import time

import rospy
from edge_slam_msgs.msg import Stats

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts'))
from bench.recorder_node import run_recorder  # noqa: E402


def main():
    out_path = rospy.myargv()[sys.argv.index('--out') + 1]

    def subscribe():
        out = open(out_path, 'w', buffering=1)

        def on_stats(msg):
            row = dict(zip(msg.names, msg.values))
            row['wall'] = time.time()
            out.write(json.dumps(row) + '\n')
        rospy.Subscriber('/edge_slam/mobile/stats', Stats, on_stats, queue_size=20)

    # Waits for the master as long as it takes, and outlives a cut link (the master is on the edge side).
    run_recorder('delivery_stats_probe', subscribe, master_timeout=None, stop_when_master_gone=False)


if __name__ == '__main__':
    main()
