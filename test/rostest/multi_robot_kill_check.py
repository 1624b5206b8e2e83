#!/usr/bin/python3
"""rostest: one of two robots dies mid-run (issue #16, faults). Both robots start together on
the two-robot synthetic sequence; once robot 2 has mapped 10 s of its walk, its mobile nodelet
manager, its nodelet loader and its player are SIGKILLed (no clean shutdown, as a robot that
loses power). Robot 1 must not notice: it keeps accepting Local-Map updates (at least 2 after
the kill), its final trajectory stays under 2 cm and its poses as tracked under 20 cm (loosely,
as multi_robot_check.py says why), every
KeyFrame it made is accounted for on the edge; robot 2's map stays on the edge (what it
inserted is in the Global-Map or culled) and the edge still answers for it."""
import sys
import unittest

import rospy
import rostest

from multi_test_support import TRACKED_BOUND_M, MultiRobotRun, kill_node
from split_test_support import node_running

KILL_AFTER_S = 10.0  # of robot 2's data


class MultiRobotKillTest(unittest.TestCase):
    def test_a_robot_that_dies_costs_the_other_nothing(self):
        run = MultiRobotRun()  # scripts/ on the path: the bench package
        from bench.multi_ate import combined_ate
        survivor, victim = run.robots['robot1'], run.robots['robot2']
        run.release_players()
        victim.wait_until(lambda: len(victim.poses) > 1 and victim.poses[-1][0] - victim.poses[0][0] >= KILL_AFTER_S, 180,
                          "%.0f s of robot 2's data tracked" % KILL_AFTER_S)
        victim.wait_until(lambda: len(victim.edge_status().inserted_ids) >= 5, 60, 'robot 2 to have a map on the edge')
        at_kill = survivor.mobile_status().accepted
        for node in ('/robot2/edge_slam/mobile_manager', '/robot2/edge_slam/mobile', '/robot2/player'):
            kill_node(node)
        print('\nrobot2 killed at its data second %.1f; robot1 had accepted %d updates' % (
            victim.poses[-1][0] - victim.poses[0][0], at_kill), file=sys.stderr)

        survivor.wait_until(lambda: not node_running('/robot1/player'), 300, "robot 1's player to finish its bag")
        survivor.wait_for_edge_settled()
        survivor.wait_for_keyframes_delivered()
        status = {name: system.edge_status() for name, system in run.robots.items()}  # robot 2's: served by the edge
        in_map = set().union(*(set(s.global_map_ids) for s in status.values()))
        final = run.final_trajectories(['robot1'], in_map)['robot1']
        ate = combined_ate([('robot1', run.groundtruth('robot1'), final[0])])
        online, matched = run.online_ate('robot1')
        mobile = survivor.mobile_status()
        lost = status['robot2']
        print('robot1: final %.2f cm (%d of %d frames anchored), as tracked %.2f cm over %d poses; updates accepted %d '
              '(%d after the kill); robot2 on the edge: inserted %d, in Global-Map %d, culled %d; merges %d' % (
                  ate['ate_rmse_m'] * 100, final[1]['anchored'], final[1]['frames'], online * 100, matched,
                  mobile.accepted, mobile.accepted - at_kill, len(lost.inserted_ids), len(lost.global_map_ids),
                  len(lost.culled_ids), len(run.merges)), file=sys.stderr)

        self.assertGreaterEqual(mobile.accepted - at_kill, 2, 'robot 1 keeps getting updates after robot 2 died')
        self.assertLess(ate['ate_rmse_m'], 0.02, "robot 1's final trajectory")
        self.assertGreater(final[1]['anchored'], 0.9 * final[1]['frames'], 'frames anchored on the Global-Map')
        self.assertLess(online, TRACKED_BOUND_M, "robot 1's poses as tracked")
        made = set(survivor.delivery_status().created_ids)
        self.assertEqual(sorted(made - set(status['robot1'].received_ids)), [], 'robot 1: KeyFrames the edge never received')
        self.assertGreater(len(lost.inserted_ids), 0)
        self.assertEqual(sorted(set(lost.inserted_ids) - set(lost.global_map_ids) - set(lost.culled_ids)), [],
                         "robot 2's map stays on the edge")


if __name__ == '__main__':
    rospy.init_node('multi_robot_kill_check')
    rostest.rosrun('edge_slam_tests', 'multi_robot_kill', MultiRobotKillTest)
