#!/usr/bin/python3
"""rostest: the embedded bag through the mobile + edge nodelets (paper 5.1 setting).
The mobile's trajectory (final: its frames re-anchored on the edge's final KeyFrames, as the
monolithic runner saves its own) is within 2 cm ATE and the poses as tracked (what the robot
navigates on) within 5 cm; the mobile makes at most 1.5x the monolithic KeyFrame density and the edge refuses
at most 15% of them by condition 2; the mobile applies >= 4 Local-Map updates, never holds
more than its cap of KeyFrames; the edge closes the loop and accounts for every KeyFrame it
accepted (in the Global-Map, or culled as redundant by Local-Mapping)."""
import os
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import String

from split_test_support import SplitSystem, ate_rmse, repo_root


class SplitPipelineTest(unittest.TestCase):
    def test_embedded_bag_through_mobile_and_edge(self):
        root = repo_root()
        loops = []
        rospy.Subscriber('/edge_slam/edge/loops', String, lambda m: loops.append(m.data))
        system = SplitSystem()
        system.wait_for_bag_end()
        system.wait_for_edge_settled()

        gt = os.path.join(root, 'bags', 'synthetic_room', 'groundtruth.txt')
        online_rmse, matched = ate_rmse(system.poses, gt)
        out = rospy.get_param('~out')
        system.wait_for_run_files(out)  # the nodelets rewrite their files every second
        from bench.final_trajectory import final_trajectory
        final, missing, total = final_trajectory(os.path.join(out, 'mobile_anchors.txt'),
                                                 os.path.join(out, 'edge_keyframes.txt'))
        rmse, _ = ate_rmse([(t,) + tuple(p[:3]) for t, p in final], gt)
        print('split run files in %s' % out, file=sys.stderr)
        mobile = system.mobile_status()
        edge = system.edge_status()
        print('ATE final %.2f cm (%d of %d frames anchored), as tracked %.2f cm over %d poses; updates received %d accepted %d (rejected: controller %d, '
              'initialising %d, redundant %d, rate %d); Local-Map peak %d / cap %d; edge inserted %d, culled %d, '
              'in Global-Map %d, loops %d' % (
                  rmse * 100, total - missing, total, online_rmse * 100, matched, mobile.received, mobile.accepted, mobile.rejected_controller,
                  mobile.rejected_initializing, mobile.rejected_redundant, mobile.rejected_keyframe_rate,
                  mobile.local_map_peak, mobile.local_map_cap, edge.inserted, len(edge.culled_ids),
                  len(edge.global_map_ids), edge.loops_closed), file=sys.stderr)

        self.assertGreater(matched, 300, 'the mobile must track most of the 901 frames')
        self.assertLess(rmse, 0.02, 'mobile trajectory (final) ATE RMSE %.2f cm' % (rmse * 100))
        self.assertGreater(total - missing, 0.9 * total, 'frames anchored on the Global-Map')
        self.assertGreaterEqual(mobile.accepted, 4)
        self.assertLessEqual(mobile.local_map_peak, 50)
        self.assertLessEqual(system.local_map_max, 50)
        self.assertGreater(system.stats_seen, 10, 'the mobile publishes ~stats every second')

        inserted, culled, in_map = set(edge.inserted_ids), set(edge.culled_ids), set(edge.global_map_ids)
        self.assertGreater(len(inserted), 20)
        self.assertEqual(len(inserted), edge.inserted, 'the id list matches the counter')
        self.assertEqual(inserted - in_map - culled, set(), 'accepted KeyFrames missing from the Global-Map')
        self.assertEqual(in_map & culled, set(), 'a culled KeyFrame is still in the Global-Map')
        self.assertTrue(culled <= inserted)

        # The robot's own pose (TF, odometry), and the mobile's KeyFrame rate: paced by the edge's
        # Local-Mapping (edge_slam/mobile_keyframe_pacing), about the monolithic system's density.
        # The reference is the monolithic system under the same pacing: KeyFrames CREATED (not
        # those left after culling) at this test's half speed, `edge_slam_run --rate 0.5`:
        # 283-313 for the 901 frames (3 runs with bf 40, 289-297 with bf 400, 2026-12-03). The
        # earlier reference, 171 kept at full speed, compared created with kept KeyFrames and
        # failed on a quick machine (263 made by the mobile, against 283-313 monolithic). The
        # paper's split made 3 of 4 frames KeyFrames (0.75 per frame); 1.5x this is 0.52.
        # 5 cm, not 2: on this sequence the poses as tracked have a known tail (README, "Fast,
        # blurred motion": in some runs (1 of 3 this stop), tracking jumps 4-8 cm after the
        # look-away turn and stays off until the loop closes; 0.8-1.1 cm otherwise). The bound
        # catches a broken update path (the full-replacement Local-Map gave 12.7 cm); the
        # distribution is measured by `make bench`'s robustness section.
        self.assertLess(online_rmse, 0.05, 'poses as tracked: ATE RMSE %.2f cm' % (online_rmse * 100))
        monolithic_keyframes_per_frame = 313.0 / 901  # created at half speed, worst of the runs above
        self.assertLessEqual(mobile.keyframes_created, 1.5 * monolithic_keyframes_per_frame * matched,
                             'mobile KeyFrames %d for %d tracked frames' % (mobile.keyframes_created, matched))
        self.assertLessEqual(edge.rejected_condition2, 0.15 * max(1, edge.received - edge.duplicates),
                             'KeyFrames refused by condition 2: %d of %d' % (edge.rejected_condition2, edge.received))

        self.assertGreaterEqual(edge.loops_closed, 1, 'the loop back to the start is closed on the edge')
        system.wait_until(lambda: loops, 5, 'a message on ~loops')
        self.assertIn('loop closed: KeyFrame', loops[0])


if __name__ == '__main__':
    rospy.init_node('split_pipeline_check')
    rostest.rosrun('edge_slam_tests', 'split_pipeline', SplitPipelineTest)
