#!/usr/bin/python3
"""Delivery across a link cut (issue #7): mobile (+ rosbag play) and edge (+ ROS master) in two
network namespaces joined by a veth pair; the link goes down for 10 s mid-bag, then up again.
Same accounting, tracking and ATE checks as the edge-restart test, plus: the mobile's Local-Map
never exceeded its cap. Needs root (ip netns); without it the test is skipped, saying why."""
import sys
import time
import os
import unittest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))  # nosetests -P adds no path
from delivery_harness import run_disturbed
from bench.netns import NamespacePair

NETNS_OK, NETNS_WHY = NamespacePair.available()


def cut_link(run):
    run.wait(lambda: run.bag_seconds() >= 10.0, 120, '10 s of bag')
    start = time.time()
    run.set_link(False)
    print('\n[link_cut] link down at bag %.1f s' % run.bag_seconds(), file=sys.stderr)
    time.sleep(10.0)
    run.set_link(True)
    return start, time.time()


@unittest.skipUnless(NETNS_OK, 'link-cut test: ' + NETNS_WHY)
class LinkCutTest(unittest.TestCase):
    def test_every_keyframe_accounted_for_across_a_link_cut(self):
        _, _, _, status = run_disturbed(self, 'link_cut', True, cut_link)
        self.assertLessEqual(status['local_map_peak'], status['local_map_cap'])


if __name__ == '__main__':
    unittest.main()
