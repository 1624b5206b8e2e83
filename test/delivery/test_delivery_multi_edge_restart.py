#!/usr/bin/python3
"""Delivery across an edge restart with two mobiles (issue #16, persistence): one edge serving
robot1 and robot2 (edge.launch mobiles:=[robot1, robot2]) and the two robots (robot.launch, the
two-robot synthetic sequence at half speed) in separate roslaunch processes on a private master.
~10 s into the data the edge process is SIGKILLed and started again 5 s later, restoring every
robot's map and deliveries from its checkpoint. Each mobile must see the new boot id and resend
what was not durable, every KeyFrame each robot made must be accounted for on the restarted edge
(received; the inserted ones in the Global-Map or culled), the restored map must hold both robots'
KeyFrames, and at the end both robots' maps are placed in the world (one merged map)."""
import json
import os
import sys
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))  # nosetests -P adds no path
from delivery_harness import ROOT, SplitRun  # noqa: E402

ROBOTS = {'robot1': 'bags/synthetic_room.bag', 'robot2': 'bags/synthetic_room_robot2.bag'}


class TwoRobotRun(SplitRun):
    """SplitRun's master and edge, with the edge serving two namespaced robots."""

    def __enter__(self):
        try:
            self.start_master()
            self.start_edge()
            for k, (robot, bag) in enumerate(ROBOTS.items()):
                self.spawn(robot, 'mobile', ['roslaunch', os.path.join(ROOT, 'launch', 'robot.launch'), 'robot:=' + robot,
                                             'robot_index:=%d' % k, 'bag:=' + os.path.join(ROOT, bag),
                                             'clock:=%s' % ('true' if k == 0 else 'false'), 'start_paused:=true',
                                             'rate:=%g' % self.rate, 'image_queue_size:=1000',
                                             'slam_config:=' + self.slam_config, 'out:=' + os.path.join(self.out, robot)])
            self.wait_for_edge()
            for robot in ROBOTS:
                self.wait(lambda: self.call('mobile', '/%s/edge_slam/mobile/delivery_status' % robot), 90, robot)
        except BaseException:
            self.__exit__(None, None, None)
            raise
        return self

    def start_edge(self):
        self.spawn('edge', 'edge', ['roslaunch', os.path.join(ROOT, 'launch', 'edge.launch'), 'mobiles:=[robot1, robot2]',
                                    'map_frame:=world', 'slam_config:=' + self.slam_config,
                                    'checkpoint_file:=' + self.checkpoint,
                                    'metrics_file:=' + os.path.join(self.out, 'edge_metrics.json'),
                                    'keyframes_file:=' + os.path.join(self.out, 'edge_keyframes.txt')])

    def release_players(self):
        import subprocess
        r = subprocess.run([sys.executable, '-m', 'bench.ros_util', 'release-players', '--robots'] + list(ROBOTS) +
                           ['--timeout', '180'], env=self.env('mobile'), capture_output=True, text=True)
        if r.returncode != 0:
            raise AssertionError('the players could not be started: ' + r.stderr[-500:])
        self.play_start = time.time()

    def players_running(self):
        import subprocess
        nodes = subprocess.run(['rosnode', 'list'], env=self.env('mobile'), capture_output=True, text=True).stdout.split()
        return [r for r in ROBOTS if '/%s/player' % r in nodes]

    def robot_status(self, robot):
        return self.call('edge', '/%s/edge_slam/edge_status' % robot)

    def edge_metrics(self):
        """The edge's metrics.json (rewritten every second), {} while there is none to read."""
        try:
            with open(os.path.join(self.out, 'edge_metrics.json')) as f:
                return json.load(f)
        except (OSError, ValueError):
            return {}

    def merges(self):
        """The merges the edge reports."""
        return self.edge_metrics().get('merges', [])

    def latched_merge(self):
        """One message of the edge's latched ~merges, heard by a listener that starts now."""
        import subprocess
        try:
            r = subprocess.run(['rostopic', 'echo', '-n', '1', '/edge_slam/edge/merges'], env=self.env('edge'),
                               capture_output=True, text=True, timeout=60)
        except subprocess.TimeoutExpired:
            return False
        return r.returncode == 0 and 'loop_keyframe' in r.stdout

    def placements(self):
        """T_world_robot of each robot index."""
        return {k: v.get('T_world_robot') for k, v in self.edge_metrics().get('robots', {}).items()}


class MultiEdgeRestartTest(unittest.TestCase):
    def test_both_robots_deliveries_survive_an_edge_restart(self):
        with TwoRobotRun('multi_edge_restart') as run:
            run.release_players()
            run.wait(lambda: run.bag_seconds() >= 10.0, 120, '10 s of data')
            before = {r: run.robot_status(r) or {} for r in ROBOTS}
            merges_before = run.merges()
            killed_at, start = run.bag_seconds(), time.time()
            run.kill_edge()
            time.sleep(5.0)  # the outage itself: the mobiles go on tracking with no edge
            run.start_edge()
            run.wait_for_edge()
            restored = {r: run.robot_status(r) for r in ROBOTS}
            print('\n[multi_edge_restart] edge SIGKILLed at data second %.1f (durable seqs %s), back after %.1f s with '
                  'KeyFrames %s restored' % (
                      killed_at, {r: s.get('durable_seq') for r, s in before.items()}, time.time() - start,
                      {r: len(s['global_map_ids']) for r, s in restored.items()}), file=sys.stderr)
            run.wait(lambda: not run.players_running(), 300, 'both players to finish')
            for robot in ROBOTS:
                run.wait(lambda: (run.call('mobile', '/%s/edge_slam/mobile/delivery_status' % robot) or {}).get(
                    'queued', 1) == 0, 60, '%s to have every KeyFrame durable on the edge' % robot)
            run.wait_for_edge_settled()
            run.wait(lambda: all(run.placements().get(str(k)) for k in range(len(ROBOTS))), 30,
                     'both robots placed in the world (edge_metrics.json)')
            # The merge history is in the checkpoint: a merge made before it is still reported by the
            # restarted edge (which has nothing to merge again then); one made after it, again.
            merges_after = run.merges()
            print('[multi_edge_restart] merges reported before the kill %d, by the restarted edge %d' % (
                len(merges_before), len(merges_after)), file=sys.stderr)
            self.assertGreaterEqual(len(merges_after), 1, 'the restarted edge reports the merge of the two maps')
            # ~merges is latched: a listener that comes after the restart still hears of the merge,
            # a merge restored from the checkpoint included (split/edge_system.h, new_merges).
            self.assertTrue(run.latched_merge(), 'the restarted edge has a merge latched on ~merges')
            for robot in ROBOTS:
                mobile = run.call('mobile', '/%s/edge_slam/mobile/delivery_status' % robot)
                edge = run.robot_status(robot)
                created, received = set(mobile['created_ids']), set(edge['received_ids'])
                print('[multi_edge_restart] %s: KeyFrames created %d, resent %d, durable %d; edge received %d, inserted '
                      '%d, in Global-Map %d, culled %d; edge restarts seen %d' % (
                          robot, len(created), mobile['resent'], mobile['durable'], len(received),
                          len(edge['inserted_ids']), len(edge['global_map_ids']), len(edge['culled_ids']),
                          mobile['edge_restarts']), file=sys.stderr)
                self.assertGreaterEqual(mobile['edge_restarts'], 1, '%s saw the new boot id' % robot)
                self.assertGreater(len(restored[robot]['global_map_ids']), 0, "%s's map was restored" % robot)
                self.assertGreater(len(created), 20, '%s made KeyFrames' % robot)
                self.assertEqual(sorted(created - received), [], '%s: KeyFrames the restarted edge never received' % robot)
                self.assertEqual(sorted(set(edge['inserted_ids']) - set(edge['global_map_ids']) - set(edge['culled_ids'])),
                                 [], '%s: inserted KeyFrames neither in the Global-Map nor culled' % robot)
                self.assertEqual(mobile['dropped_by_bound'] + mobile['dropped_by_outbox'], 0)


if __name__ == '__main__':
    unittest.main()
