#!/usr/bin/env python3
"""bench.multi_ate, the combined ATE of a multi-robot run (evo's API, run by the venv python) on
small synthetic TUM files: two robots on two halves of one ground truth, moved together by one
rigid motion, have no error; a robot whose map is misplaced in the world shows as error in the
combined figure while each robot alone aligns perfectly; robots whose stamps overlap pair only
with their own ground truth; bad input is one clear line and exit status 1."""
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
from bench import ate, multi_ate  # noqa: E402

# 20 s at 30 Hz along a curve: robot A has the first half, robot B the second.
N = 600
T = 100.0 + np.arange(N) / 30.0
XYZ = np.stack([np.arange(N) / 60.0, 0.4 * np.sin(np.arange(N) / 25.0), 0.2 * np.cos(np.arange(N) / 40.0)], 1)
Q = Rotation.from_euler('z', (np.arange(N) / 150.0)[:, None]).as_quat()
WORLD = Rotation.from_euler('xyz', [0.2, -0.4, 1.3])  # the world frame of the estimate vs the ground truth's
SHIFT = np.array([1.0, -0.5, 2.0])
A, B = slice(0, N // 2), slice(N // 2, N)


def in_world(xyz):
    return WORLD.apply(xyz) + SHIFT


def write_tum(path, t, xyz, q=None):
    q = np.tile([0, 0, 0, 1.0], (len(t), 1)) if q is None else q
    with open(path, 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw\n')
        for s, p, r in zip(t, xyz, q):
            f.write('%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n' % ((s,) + tuple(p) + tuple(r)))


def traj(t, xyz):
    return ate.trajectory(t, xyz)


class MultiAteTest(unittest.TestCase):

    def test_two_robots_in_one_world_frame_have_no_error(self):
        res = multi_ate.combined_ate([('robot1', ate.trajectory(T[A], XYZ[A], Q[A]), traj(T[A], in_world(XYZ[A]))),
                                      ('robot2', ate.trajectory(T[B], XYZ[B], Q[B]), traj(T[B], in_world(XYZ[B])))])
        self.assertLess(res['ate_rmse_m'], 1e-9)
        self.assertEqual(res['ate_pairs'], N)
        self.assertEqual(res['robots']['robot1']['ate_pairs'], N // 2)
        self.assertLess(res['robots']['robot2']['ate_rmse_m'], 1e-9)

    def test_a_misplaced_robot_map_shows_in_the_combined_figure_only(self):
        # Robot 2's map is placed in the world 10 cm and 3 degrees off: alone it aligns perfectly.
        off = Rotation.from_euler('z', 0.05)
        est_b = off.apply(in_world(XYZ[B])) + [0.1, 0.0, 0.0]
        alone = ate.ate_stats(traj(T[B], XYZ[B]), traj(T[B], est_b))
        self.assertLess(alone['ate_rmse_m'], 1e-9)
        res = multi_ate.combined_ate([('robot1', traj(T[A], XYZ[A]), traj(T[A], in_world(XYZ[A]))),
                                      ('robot2', traj(T[B], XYZ[B]), traj(T[B], est_b))])
        self.assertGreater(res['ate_rmse_m'], 0.02)
        self.assertGreater(res['robots']['robot1']['ate_rmse_m'], 0.01, 'one alignment: robot 1 pays too')
        # Robot 2 alone 1 cm off: a translation-only alignment would leave 5 mm on every pose
        # (the rotation takes a little more); aligned alone, nothing.
        est_b = in_world(XYZ[B]) + [0.0, 0.01, 0.0]
        res = multi_ate.combined_ate([('robot1', traj(T[A], XYZ[A]), traj(T[A], in_world(XYZ[A]))),
                                      ('robot2', traj(T[B], XYZ[B]), traj(T[B], est_b))])
        self.assertGreater(res['ate_rmse_m'], 0.003)
        self.assertLessEqual(res['ate_rmse_m'], 0.005 + 1e-9)

    def test_overlapping_stamps_pair_with_their_own_ground_truth(self):
        # Robot 2 played on robot 1's clock: the same stamps as robot 1, its own ground truth.
        res = multi_ate.combined_ate([('robot1', traj(T[A], XYZ[A]), traj(T[A], in_world(XYZ[A]))),
                                      ('robot2', traj(T[A], XYZ[B]), traj(T[A], in_world(XYZ[B])))])
        self.assertLess(res['ate_rmse_m'], 1e-9)
        self.assertEqual(res['ate_pairs'], N)

    def test_bad_input(self):
        with self.assertRaisesRegex(ValueError, 'robot2: no poses associated'):
            multi_ate.combined_ate([('robot1', traj(T[A], XYZ[A]), traj(T[A], XYZ[A])),
                                    ('robot2', traj(T[A], XYZ[A]), traj(T[B], XYZ[B]))])
        with self.assertRaisesRegex(ValueError, 'differ'):
            multi_ate.combined_ate([('r', traj(T[A], XYZ[A]), traj(T[A], XYZ[A]))] * 2)

    def test_command_line_on_files(self):
        with tempfile.TemporaryDirectory() as d:
            files = {}
            for name, part in (('robot1', A), ('robot2', B)):
                files[name] = (os.path.join(d, name + '_gt.txt'), os.path.join(d, name + '_traj.txt'))
                write_tum(files[name][0], T[part], XYZ[part], Q[part])
                write_tum(files[name][1], T[part], in_world(XYZ[part]))
            cmd = [VENV_PYTHON, '-m', 'bench.multi_ate', '--json']
            for name, (gt, est) in files.items():
                cmd += ['--robot', name, gt, est]
            r = subprocess.run(cmd, capture_output=True, text=True, cwd=SCRIPTS, timeout=120)
            self.assertEqual(r.returncode, 0, r.stderr)
            res = json.loads(r.stdout)
            self.assertLess(res['ate_rmse_m'], 1e-5)  # 6-decimal files
            self.assertEqual(sorted(res['robots']), ['robot1', 'robot2'])
            missing = subprocess.run(cmd[:4] + ['--robot', 'robot2', os.path.join(d, 'none.txt'), files['robot2'][1]],
                                     capture_output=True, text=True, cwd=SCRIPTS, timeout=120)
            self.assertEqual(missing.returncode, 1)
            self.assertIn('bench.multi_ate', missing.stderr)
            self.assertEqual(len(missing.stderr.strip().splitlines()), 1, missing.stderr)


if __name__ == '__main__':
    unittest.main()
