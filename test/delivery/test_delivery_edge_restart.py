#!/usr/bin/python3
"""Delivery across an edge restart (issue #7): mobile and edge in two processes on the embedded
bag (half speed); the edge process is SIGKILLed ~10 s into the bag and started again 5 s later,
restoring its Global-Map from the checkpoint. Every KeyFrame the mobile made must be accounted
for on the edge (received: in the Global-Map, culled, or rejected by condition 1/2), the mobile
keeps tracking through the outage, and its ATE stays within 2x an undisturbed run's."""
import sys
import time
import os
import unittest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))  # nosetests -P adds no path
from delivery_harness import run_disturbed


def kill_and_restart(run):
    run.wait(lambda: run.bag_seconds() >= 10.0, 120, '10 s of bag')
    cp = run.call('edge', '/edge_slam/edge/status') or {}
    start = time.time()
    run.kill_edge()
    print('\n[edge_restart] edge SIGKILLed at bag %.1f s (checkpoints written %s, durable seq %s)' % (
        run.bag_seconds(), cp.get('checkpoints'), cp.get('durable_seq')), file=sys.stderr)
    time.sleep(5.0)
    run.start_edge()
    run.wait_for_edge()
    status = run.call('edge', '/edge_slam/edge/status')
    print('[edge_restart] edge back after %.1f s with %d KeyFrames restored (seq %d durable)' % (
        time.time() - start, status['global_map_keyframes'], status['durable_seq']), file=sys.stderr)
    return start, time.time()


class EdgeRestartTest(unittest.TestCase):
    def test_every_keyframe_accounted_for_across_an_edge_restart(self):
        _, mobile, edge, _ = run_disturbed(self, 'edge_restart', False, kill_and_restart)
        self.assertGreaterEqual(mobile['edge_restarts'], 1, 'the mobile saw the new boot id')


if __name__ == '__main__':
    unittest.main()
