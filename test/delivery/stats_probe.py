#!/usr/bin/python3
"""Writes every edge_slam_msgs/Stats message of the mobile as one JSON line {"wall": t, name: value}
(line-buffered), for the delivery tests. stats_probe.py --out stats.jsonl; stops on SIGINT/SIGTERM."""
import json
import signal
import sys
import time

import rosgraph
import rospy
from edge_slam_msgs.msg import Stats


def main():
    out_path = rospy.myargv()[sys.argv.index('--out') + 1]
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    while not rosgraph.is_master_online():
        if stop:
            return
        time.sleep(0.2)
    out = open(out_path, 'w', buffering=1)

    def on_stats(msg):
        row = dict(zip(msg.names, msg.values))
        row['wall'] = time.time()
        out.write(json.dumps(row) + '\n')
    rospy.init_node('delivery_stats_probe', anonymous=True, disable_signals=True)
    rospy.Subscriber('/edge_slam/mobile/stats', Stats, on_stats, queue_size=20)
    while not stop:
        time.sleep(0.2)


if __name__ == '__main__':
    main()
