#!/usr/bin/env python3
"""bench.multi_eval on a fake multi-robot output folder (venv python, evo): robot 2 was played on
robot 1's clock (its stamps moved by -5 s), so its ground truth is moved by the same offset before
any ATE; per-robot online ATE in each robot's own frame, combined final ATE in the world frame
with one alignment; the merge count from the edge's metrics, else the edge's CSV "merge" events;
a robot without a final trajectory leaves the combined figure null with a note."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from scipy.spatial.transform import Rotation

SCRIPTS = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts'))
VENV_PYTHON = os.path.join(os.path.dirname(SCRIPTS), '.venv', 'bin', 'python3')
sys.path.insert(0, SCRIPTS)
from bench import multi_eval  # noqa: E402

N = 300
T = 100.0 + np.arange(N) / 30.0  # the sequence's stamps: robot 1 has the first half, robot 2 the second
XYZ = np.stack([np.arange(N) / 60.0, 0.4 * np.sin(np.arange(N) / 25.0), 0.2 * np.cos(np.arange(N) / 40.0)], 1)
WORLD = Rotation.from_euler('xyz', [0.2, -0.4, 1.3])
A, B = slice(0, N // 2), slice(N // 2, N)
OFFSET2 = float(T[0] - T[N // 2])  # robot 2's stamps moved onto robot 1's clock


def write_tum(path, t, xyz):
    with open(path, 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw\n')
        for s, p in zip(t, xyz):
            f.write('%.6f %.6f %.6f %.6f 0 0 0 1\n' % ((s,) + tuple(p)))


def fake_run(d, final2=True):
    out = os.path.join(d, 'out')
    robots = []
    for k, part, offset in ((1, A, 0.0), (2, B, OFFSET2)):
        folder = os.path.join(d, 'data_part%d' % k)
        os.makedirs(folder)
        write_tum(os.path.join(folder, 'groundtruth.txt'), T[part], XYZ[part])
        r = os.path.join(out, 'robot%d' % k)
        os.makedirs(r)
        t = T[part] + offset
        # Online: each robot in its own map frame (any rigid motion). Final: the world frame.
        own = Rotation.from_euler('z', 0.3 * k)
        write_tum(os.path.join(r, 'trajectory_online.txt'), t, own.apply(XYZ[part]) + [k, 0, 0])
        if k == 1 or final2:
            write_tum(os.path.join(r, 'trajectory.txt'), t, WORLD.apply(XYZ[part]))
        with open(os.path.join(r, 'mobile_metrics.json'), 'w') as f:
            json.dump({'frames': 150, 'frames_tracked': 150, 'keyframes': 12, 'times_lost': 0}, f)
        robots.append(('robot%d' % k, folder, offset, 'folder'))
    return out, robots


class MultiEvalTest(unittest.TestCase):

    def test_figures_of_a_two_robot_run(self):
        with tempfile.TemporaryDirectory() as d:
            out, robots = fake_run(d)
            with open(os.path.join(out, 'edge_metrics.json'), 'w') as f:
                json.dump({'merges': [{'keyframe': 16777220, 'loop_keyframe': 24, 'robot': 1, 'loop_robot': 0, 'matches': 500,
                                       'T_into_from': [0, 0, 0, 0, 0, 0, 1]}],
                           'loops_closed': 0, 'keyframes': {'inserted': 24}}, f)
            m, lines = multi_eval.summarize(out, robots)
            self.assertLess(m['robots']['robot1']['ate_online_rmse_m'], 1e-5)
            self.assertLess(m['robots']['robot2']['ate_online_rmse_m'], 1e-5, 'ground truth moved by the offset')
            self.assertEqual(m['robots']['robot2']['ate_online_pairs'], N // 2)
            self.assertLess(m['ate_rmse_m'], 1e-5)
            self.assertEqual(m['ate_pairs'], N)
            self.assertEqual(m['merges'], 1)
            self.assertEqual(m['notes'], [])
            with open(os.path.join(out, 'metrics.json')) as f:
                self.assertEqual(json.load(f)['merges'], 1)
            self.assertTrue(any(l.startswith('multi: combined final ATE') for l in lines))
            with open(os.path.join(out, 'robot2', 'groundtruth.txt')) as f:
                first = [l for l in f if not l.startswith('#')][0]
            self.assertAlmostEqual(float(first.split()[0]), T[0], places=5)

    def test_merges_from_the_edge_metrics_then_its_events(self):
        with tempfile.TemporaryDirectory() as d:
            out, robots = fake_run(d)
            self.assertIsNone(multi_eval.merges_count(out)[0])
            with open(os.path.join(out, 'edge_stats.csv'), 'w') as f:
                f.write('event,data_time,detail\nkeyframe,1.0,\nmerge,2.0,a\nmerge,3.0,b\n')
            self.assertEqual(multi_eval.merges_count(out), (2, 'edge_stats.csv "merge" events'))
            with open(os.path.join(out, 'edge_metrics.json'), 'w') as f:
                json.dump({'merges': [{'keyframe': 16777220, 'loop_keyframe': 24, 'robot': 1, 'loop_robot': 0,
                                       'matches': 639, 'T_into_from': [0, 0, 0, 0, 0, 0, 1]}]}, f)
            self.assertEqual(multi_eval.merges_count(out), (1, 'edge_metrics.json merges'))

    def test_a_robot_without_final_trajectory(self):
        with tempfile.TemporaryDirectory() as d:
            out, robots = fake_run(d, final2=False)
            m, lines = multi_eval.summarize(out, robots)
            self.assertIsNone(m['ate_rmse_m'])
            self.assertIsNone(m['robots']['robot2']['ate_final_rmse_m'])
            self.assertIsNotNone(m['robots']['robot2']['ate_online_rmse_m'])
            self.assertTrue(any('no trajectory.txt' in n for n in m['notes']), m['notes'])
            self.assertTrue(any('no edge_metrics.json' in n for n in m['notes']), m['notes'])

    def test_command_line(self):
        with tempfile.TemporaryDirectory() as d:
            out, robots = fake_run(d)
            cmd = [VENV_PYTHON, '-m', 'bench.multi_eval', out]
            for name, folder, offset, source in robots:
                cmd += ['--robot', name, folder, repr(offset), source]
            r = subprocess.run(cmd, capture_output=True, text=True, cwd=SCRIPTS, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn('multi: combined final ATE', r.stdout)
            bad = subprocess.run(cmd[:4] + ['--robot', 'robot9', os.path.join(d, 'none'), '0', 'bag'],
                                 capture_output=True, text=True, cwd=SCRIPTS, timeout=120)
            self.assertEqual(bad.returncode, 1)
            self.assertIn('no groundtruth.txt', bad.stderr)


if __name__ == '__main__':
    unittest.main()
