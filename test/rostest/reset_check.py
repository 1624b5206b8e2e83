#!/usr/bin/python3
"""rostest: the reset service (paper 4.7.4). With playback paused, a reset on the mobile clears
its Local-Map and, through the reset-flagged KeyFrame, the edge's Global-Map; when playback
resumes both sides map again from scratch."""
import sys
import unittest

import rospy
import rostest

from split_test_support import SplitSystem


class ResetTest(unittest.TestCase):
    def test_reset_clears_both_sides(self):
        system = SplitSystem()
        system.wait_for_tracking()
        system.wait_until(lambda: system.edge_status().global_map_keyframes >= 4, 90, 'a Global-Map of 4 KeyFrames')
        system.pause_player(True)
        system.wait_for_pipeline_drained()  # frames and KeyFrames in flight arrive
        before = system.edge_status()
        self.assertGreaterEqual(before.global_map_keyframes, 4)
        self.assertGreater(system.mobile_status().local_map_keyframes, 0)

        reply = system.reset()
        self.assertTrue(reply.success, reply.message)
        self.assertEqual(system.mobile_status().local_map_keyframes, 0, 'the Local-Map is cleared at once')
        system.wait_until(lambda: system.edge_status().resets >= 1, 20, 'the edge to receive the reset KeyFrame')
        after = system.edge_status()
        print('before reset: edge %d KFs; after: %d KFs, %d ids accepted, resets %d' % (
            before.global_map_keyframes, after.global_map_keyframes, len(after.inserted_ids), after.resets),
            file=sys.stderr)
        self.assertEqual(after.global_map_keyframes, 0)
        self.assertEqual(after.global_map_points, 0)
        self.assertEqual(list(after.inserted_ids), [])

        system.pause_player(False)
        system.wait_until(lambda: system.mobile_status().local_map_keyframes > 0, 60, 'the mobile to re-initialise')
        system.wait_until(lambda: system.edge_status().global_map_keyframes > 0, 60, 'the edge to map again')


if __name__ == '__main__':
    rospy.init_node('reset_check')
    rostest.rosrun('edge_slam_tests', 'reset', ResetTest)
