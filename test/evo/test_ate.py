#!/usr/bin/env python3
"""bench.ate, the project's one ATE tool (evo's API, run by the venv python): the ATE of a
rigidly moved copy of the ground truth is zero, a known offset gives its RMSE, the association
tolerance is evo's 0.01 s, and largest_update_jump finds a step put into the trajectory at an
update (and nothing at the other updates)."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from scipy.spatial.transform import Rotation

SCRIPTS = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts'))
sys.path.insert(0, SCRIPTS)
from bench import ate  # noqa: E402

# 10 s at 30 Hz along a curve, with a yaw that changes (a trajectory that pins the alignment).
T = 100.0 + np.arange(300) / 30.0
GT_XYZ = np.stack([np.arange(300) / 30.0, 0.3 * np.sin(np.arange(300) / 20.0), 0.1 * np.cos(np.arange(300) / 35.0)], 1)
GT_Q = Rotation.from_euler('z', (np.arange(300) / 100.0)[:, None]).as_quat()
MOVE = Rotation.from_euler('xyz', [0.3, -0.2, 1.0])  # an arbitrary rigid motion of the estimate's frame
SHIFT = np.array([0.5, -2.0, 1.0])


def moved(xyz):
    return MOVE.apply(xyz) + SHIFT


def write_tum(path, t, xyz, q):
    with open(path, 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw\n')
        for s, p, r in zip(t, xyz, q):
            f.write('%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f\n' % ((s,) + tuple(p) + tuple(r)))


class AteTest(unittest.TestCase):

    def test_rigidly_moved_ground_truth_has_no_error(self):
        s = ate.ate_stats(ate.trajectory(T, GT_XYZ, GT_Q), ate.trajectory(T, moved(GT_XYZ)))
        self.assertLess(s['ate_rmse_m'], 1e-9)
        self.assertEqual(s['ate_pairs'], 300)

    def test_known_offset_gives_its_rmse(self):
        est = GT_XYZ.copy()
        est[::2] += [0.0, 0.0, 0.01]  # every other pose 1 cm up: after alignment +-5 mm
        s = ate.ate_stats(ate.trajectory(T, GT_XYZ), ate.trajectory(T, moved(est)))
        self.assertAlmostEqual(s['ate_rmse_m'], 0.005, delta=2e-4)

    def test_association_tolerance_is_evos_default(self):
        self.assertEqual(ate.MAX_DIFF, 0.01)
        ref = ate.trajectory(T, GT_XYZ)
        self.assertEqual(ate.ate_stats(ref, ate.trajectory(T + 0.009, GT_XYZ))['ate_pairs'], 300)
        with self.assertRaises(ValueError):
            ate.ate_stats(ref, ate.trajectory(T + 0.012, GT_XYZ))  # 12 ms from every ground-truth stamp

    def test_largest_jump_is_the_step_put_in_at_an_update(self):
        est = GT_XYZ.copy()
        est[T > 105.0] += [0.0, 0.03, 0.04]  # 5 cm step between the frames around t = 105.0
        est[T > 108.0] += [0.002, 0.0, 0.0]  # 2 mm step around t = 108.0
        online = ate.trajectory(T, moved(est))
        jump, per_update = ate.largest_update_jump(ate.trajectory(T, GT_XYZ), online, [102.0, 105.01, 108.0, 99.0, 200.0])
        # The whole-trajectory alignment of a non-rigid estimate is slightly off: within 1 mm.
        self.assertAlmostEqual(jump, 0.05, delta=1e-3)
        self.assertEqual([t for t, _ in per_update], [102.0, 105.01, 108.0], 'stamps outside the trajectory skipped')
        by_stamp = dict(per_update)
        self.assertLess(by_stamp[102.0], 5e-4, 'a smooth stretch: online step = ground-truth step')
        self.assertAlmostEqual(by_stamp[108.0], 0.002, delta=5e-4)

    def test_no_update_inside_the_trajectory(self):
        jump, per_update = ate.largest_update_jump(ate.trajectory(T, GT_XYZ), ate.trajectory(T, GT_XYZ), [50.0])
        self.assertIsNone(jump)
        self.assertEqual(per_update, [])

    def test_command_line_on_files_with_update_stamps_from_the_mobile_csv(self):
        est = GT_XYZ.copy()
        est[T > 104.0] += [0.0, 0.0, 0.02]
        with tempfile.TemporaryDirectory() as d:
            gt, traj, csv = (os.path.join(d, n) for n in ('groundtruth.txt', 'trajectory.txt', 'mobile_stats.csv'))
            write_tum(gt, T, GT_XYZ, GT_Q)
            write_tum(traj, T, moved(est), GT_Q)
            with open(csv, 'w') as f:
                f.write('wall_time,data_time,event,seq,bytes,latency_ms,duration_ms,map_keyframes,frame_stamp,'
                        'state,kind,decision,deferred,keyframes,points,detail\n')
                # installed after the frame of 104.01 s (the bag's clock had gone on to 104.2): counts there
                f.write('1.0,104.2,update,1,1000,3.0,12.0,6,104.01,,periodic,accepted,0,-1,-1,\n')
                f.write('2.0,106.2,update,2,1000,3.0,-1,6,106.01,,periodic,controller,0,-1,-1,\n')  # refused
            r = subprocess.run([sys.executable, '-m', 'bench.ate', gt, traj, '--json', '--update-stamps-from', csv],
                               cwd=SCRIPTS, capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            out = json.loads(r.stdout)
            bad = subprocess.run([sys.executable, '-m', 'bench.ate', gt, os.path.join(d, 'missing.txt')],
                                 cwd=SCRIPTS, capture_output=True, text=True)
        self.assertLess(out['ate_rmse_m'], 0.011)
        self.assertAlmostEqual(out['update_jump_max_m'], 0.02, delta=1e-3)
        self.assertEqual([t for t, _ in out['update_jumps']], [104.01])
        self.assertNotEqual(bad.returncode, 0)
        self.assertIn('bench.ate', bad.stderr)


if __name__ == '__main__':
    unittest.main()
