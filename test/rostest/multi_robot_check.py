#!/usr/bin/python3
"""rostest: two mobiles on one edge (issue #16), the two-robot synthetic sequence. Both robots'
players start together once every node is up; when both bags are played and the edge has
settled: the two maps merged once; both robots' final trajectories, in robot 1's frame (the
world), have an ATE under 2 cm against their common ground truth with ONE alignment for both;
each robot accepted at least 3 Local-Map updates; every KeyFrame each robot made reached the
edge, and those the edge inserted are in the Global-Map or culled. Each robot's poses as tracked
(what it navigates on, in its own map frame) are printed and bounded loosely, at 20 cm, to catch
a broken map: after a merge the loop corrections between the two robots' maps step a robot's
online pose (a 10 cm step at a loop 3 s after the merge in a fresh-clone run: 6.19 cm RMSE;
0.9-1.3 cm in the other runs). The issue's accuracy figure is the final one."""
import sys
import unittest

import rospy
import rostest

from multi_test_support import ROBOTS, TRACKED_BOUND_M, MultiRobotRun
from split_test_support import node_running


class MultiRobotTest(unittest.TestCase):
    def test_two_mobiles_on_one_edge(self):
        run = MultiRobotRun()  # scripts/ on the path: the bench package
        from bench.multi_ate import combined_ate
        run.release_players()
        run.first.wait_until(lambda: not any(node_running('/%s/player' % r) for r in ROBOTS), 400,
                             'both players to finish their bags')
        run.first.wait_for_edge_settled()
        for system in run.robots.values():
            system.wait_for_keyframes_delivered()
        status = {name: system.edge_status() for name, system in run.robots.items()}
        in_map = set().union(*(set(s.global_map_ids) for s in status.values()))
        finals = run.final_trajectories(ROBOTS, in_map)

        lines, online, anchored = [], {}, {}
        for name, system in run.robots.items():
            online[name], matched = run.online_ate(name)
            counts = finals[name][1]
            anchored[name] = counts['anchored'] / max(1, counts['frames'])
            mobile, edge = system.mobile_status(), status[name]
            lines.append('%s: as tracked %.2f cm over %d poses (own frame); %d of %d frames anchored; updates received %d '
                         'accepted %d; KeyFrames made %d, edge received %d, inserted %d, in Global-Map %d, culled %d, '
                         'refused by condition 2 %d' % (
                             name, online[name] * 100, matched, counts['anchored'], counts['frames'], mobile.received,
                             mobile.accepted, len(system.delivery_status().created_ids), len(edge.received_ids),
                             len(edge.inserted_ids), len(edge.global_map_ids), len(edge.culled_ids),
                             edge.rejected_condition2))
        both = combined_ate([(name, run.groundtruth(name), finals[name][0]) for name in ROBOTS])
        print('\n'.join(['', 'run files in %s' % run.out] + lines + [
            'merges: %s' % ['%s into %s (KeyFrame %d ~ %d, %d matches)' % (
                m.robot, m.into_robot, m.keyframe, m.loop_keyframe, m.matches) for m in run.merges],
            'final trajectories in the world frame, one alignment: ATE %.2f cm over %d poses (%s)' % (
                both['ate_rmse_m'] * 100, both['ate_pairs'], ', '.join(
                    '%s %.2f cm' % (n, r['ate_rmse_m'] * 100) for n, r in both['robots'].items()))]), file=sys.stderr)

        self.assertEqual(len(run.merges), 1, 'one merge of the two maps')
        self.assertEqual({run.merges[0].robot, run.merges[0].into_robot}, set(ROBOTS))
        self.assertLess(both['ate_rmse_m'], 0.02, 'both final trajectories in one frame, one alignment')
        for name, system in run.robots.items():
            self.assertGreater(both['robots'][name]['ate_pairs'], 700, '%s in the alignment' % name)
            self.assertGreater(anchored[name], 0.9, '%s: frames anchored on the Global-Map' % name)
            self.assertLess(online[name], TRACKED_BOUND_M, '%s: poses as tracked' % name)
            self.assertGreaterEqual(system.mobile_status().accepted, 3, '%s: Local-Map updates accepted' % name)
            edge = status[name]
            made = set(system.delivery_status().created_ids)
            self.assertGreater(len(made), 20, '%s made KeyFrames' % name)
            self.assertEqual(sorted(made - set(edge.received_ids)), [], '%s: KeyFrames the edge never received' % name)
            self.assertEqual(sorted(set(edge.inserted_ids) - set(edge.global_map_ids) - set(edge.culled_ids)), [],
                             '%s: inserted KeyFrames neither in the Global-Map nor culled' % name)


if __name__ == '__main__':
    rospy.init_node('multi_robot_check')
    rostest.rosrun('edge_slam_tests', 'multi_robot', MultiRobotTest)
