#!/usr/bin/env python3
"""Two mobiles and one edge on the two-robot synthetic sequence (issue #16 acceptance), the real
nodelets through `make eval MODE=multi` (scripts/eval_multi.sh: one ROS master of its own on a free
port, both robots' bags released together, waits on the players and the edge's status, never on
a fixed sleep): the maps merge once; both robots' final trajectories, in robot 1's frame (the
world), have an ATE under 2 cm against the common ground truth with ONE alignment for both; each
robot accepted at least 3 Local-Map updates; every KeyFrame each robot created reached the edge
and is accounted for (inserted ones in the Global-Map or culled, none lost).
Runs in the venv python (evo). Robot 2's data: scripts/make_dataset.sh --robot2 (make test does it)."""
import json
import os
import socket
import subprocess
import tempfile
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


def load(path):
    with open(path) as f:
        return json.load(f)


class MultiRobotRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for d in ('bags/synthetic_room', 'bags/synthetic_room_robot2'):
            if not os.path.isfile(os.path.join(ROOT, d, 'groundtruth.txt')):
                raise unittest.SkipTest(f'{d} not generated (scripts/make_dataset.sh --robot2)')
        cls.out = tempfile.mkdtemp(prefix='edge_slam_multi_robot_run_')  # a folder of its own
        # Half speed: two mobiles, the edge and two players share 2 cores with the rest of make
        # test. At full speed the clock robot's rosbag play fell behind in bursts (its /clock held
        # at 0.8 s, then 16.1 s, for several wall seconds) and the edge's update timer, on data
        # time, fired twice instead of five times. Updates per data second are the same.
        env = dict(os.environ, DATASET='bags/synthetic_room', MODE='multi', OUT=cls.out,
                   EVAL_ROS_PORT=str(free_port()), PATH='/usr/bin:' + os.environ.get('PATH', ''),
                   MULTI_LAUNCH_ARGS='rate:=0.5')
        env.pop('ROS_MASTER_URI', None)
        run = subprocess.run(['bash', 'scripts/eval.sh'], cwd=ROOT, env=env, capture_output=True, text=True,
                             timeout=420)
        cls.log = run.stdout[-3000:] + run.stderr[-3000:]
        cls.rc = run.returncode

    def setUp(self):
        self.assertEqual(self.rc, 0, self.log)
        self.metrics = load(os.path.join(self.out, 'metrics.json'))
        self.edge = load(os.path.join(self.out, 'edge_metrics.json'))

    def test_the_maps_merge_once(self):
        self.assertEqual(len(self.edge['merges']), 1, self.edge['merges'])
        merge = self.edge['merges'][0]
        self.assertEqual({merge['robot'], merge['loop_robot']}, {0, 1})
        placed = [r['T_world_robot'] for r in self.edge['robots'].values()]
        self.assertTrue(all(p is not None for p in placed), 'both robots placed in the world')

    def test_both_trajectories_in_one_frame_under_2_cm(self):
        self.assertIsNotNone(self.metrics['ate_rmse_m'], self.metrics.get('notes'))
        print('combined final ATE %.2f cm over %d poses' % (self.metrics['ate_rmse_m'] * 100, self.metrics['ate_pairs']))
        self.assertLess(self.metrics['ate_rmse_m'], 0.02)
        self.assertGreater(self.metrics['ate_pairs'], 1500, 'both robots in the alignment')

    def test_each_robot_accepts_updates(self):
        for k in (1, 2):
            m = load(os.path.join(self.out, f'robot{k}', 'mobile_metrics.json'))
            self.assertGreaterEqual(m['updates']['accepted'], 3, f'robot{k}: {m["updates"]}')

    def test_every_keyframe_is_accounted_for(self):
        for k in (1, 2):
            m = load(os.path.join(self.out, f'robot{k}', 'mobile_metrics.json'))
            account = self.edge['robots'][str(k - 1)]['keyframe_account']
            self.assertEqual(account['received'], m['keyframes'], f'robot{k}: every KeyFrame it made reached the edge')
            self.assertEqual(account['lost'], 0, account)
            self.assertEqual(account['in_map'] + account['culled'], account['inserted'], account)
            self.assertEqual(self.edge['robots'][str(k - 1)]['foreign_ids'], 0)


if __name__ == '__main__':
    unittest.main()
