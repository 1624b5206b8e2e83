#!/usr/bin/env python3
"""split_dataset.py on a tiny TUM folder: consecutive parts of the colour frames, each with its
depth frames and the ground truth of its span (source lines unchanged), an optional
overlap, symlinks for the rest, and bad input refused with one clear error."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
SCRIPT = os.path.join(ROOT, 'scripts', 'split_dataset.py')
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
sys.path.insert(0, os.path.join(ROOT, 'edge_slam_common', 'python'))
from split_dataset import ranges, split  # noqa: E402
from edge_slam_common.tum import read_list, read_poses  # noqa: E402


def entries(stamps, folder):
    return [((int(s), int(round((s - int(s)) * 1e9))), '%s/%.6f.png' % (folder, s), n) for n, s in enumerate(stamps, 1)]


def poses(stamps):
    return [((int(s), int(round((s - int(s)) * 1e9))), [0, 0, 0, 0, 0, 0, 1], n) for n, s in enumerate(stamps, 1)]


def make_folder(d, n=12):
    src = os.path.join(d, 'fr1_tiny')
    os.makedirs(os.path.join(src, 'rgb'))
    os.makedirs(os.path.join(src, 'depth'))
    with open(os.path.join(src, 'rgb.txt'), 'w') as f:
        f.write('# color\n' + ''.join('%.6f rgb/%d.png\n' % (1.0 + i / 10.0, i) for i in range(n)))
    with open(os.path.join(src, 'depth.txt'), 'w') as f:
        f.write(''.join('%.6f depth/%d.png\n' % (1.005 + i / 10.0, i) for i in range(n)))
    with open(os.path.join(src, 'groundtruth.txt'), 'w') as f:
        f.write('# gt\n' + ''.join('%.6f 0.123456789 0 0 0 0 0 1\n' % (0.9 + i / 20.0) for i in range(2 * n + 4)))
    with open(os.path.join(src, 'accelerometer.txt'), 'w') as f:
        f.write('# acc\n')
    return src


class SplitTest(unittest.TestCase):
    def test_ranges_are_consecutive_and_cover_every_frame(self):
        self.assertEqual(ranges(10, 2, 0), [(0, 5), (5, 10)])
        self.assertEqual(ranges(11, 3, 0), [(0, 4), (4, 8), (8, 11)])
        self.assertEqual(ranges(10, 2, 3), [(0, 8), (5, 10)], 'overlap extends all parts but the last')
        self.assertEqual(ranges(10, 2, 50), [(0, 10), (5, 10)])
        for bad in ((10, 1, 0), (3, 2, 0), (10, 2, -1)):
            with self.assertRaises(ValueError):
                ranges(*bad)

    def test_each_part_has_its_depth_and_ground_truth(self):
        rgb = entries([1.0, 1.1, 1.2, 1.3, 1.4, 1.5], 'rgb')
        depth = entries([1.01, 1.09, 1.21, 1.24, 1.32, 1.41, 1.52], 'depth')  # 1.24: nobody's nearest, kept
        gt = poses([0.85, 0.95, 1.15, 1.25, 1.35, 1.55, 1.65])
        (c1, d1, g1), (c2, d2, g2) = split(rgb, depth, gt, 2)
        self.assertEqual([c[1] for c in c1], ['rgb/1.000000.png', 'rgb/1.100000.png', 'rgb/1.200000.png'])
        self.assertEqual([c[1] for c in c2], ['rgb/1.300000.png', 'rgb/1.400000.png', 'rgb/1.500000.png'])
        self.assertEqual([d[1] for d in d1], ['depth/1.010000.png', 'depth/1.090000.png', 'depth/1.210000.png',
                                              'depth/1.240000.png'])
        self.assertEqual([d[1] for d in d2], ['depth/1.320000.png', 'depth/1.410000.png', 'depth/1.520000.png'])
        self.assertEqual([p[2] for p in g1], [2, 3, 4], 'ground truth from 0.9 to 1.3 s (0.1 s margin)')
        self.assertEqual([p[2] for p in g2], [4, 5, 6], 'ground truth from 1.2 to 1.6 s')

    def test_parts_on_disk_and_bad_input(self):
        with tempfile.TemporaryDirectory() as d:
            src = make_folder(d)
            dsts = [os.path.join(d, 'fr1_tiny_part%d' % k) for k in (1, 2)]
            out = subprocess.run(['/usr/bin/python3', SCRIPT, src] + dsts + ['--json', '--overlap', '2'],
                                 capture_output=True, text=True)
            self.assertEqual(out.returncode, 0, out.stderr)
            report = json.loads(out.stdout)
            self.assertEqual([r['colour'] for r in report], [8, 6])
            self.assertAlmostEqual(report[1]['first_stamp'], 1.6, places=6, msg='robot 2 starts mid-sequence')
            rgb2 = read_list(os.path.join(dsts[1], 'rgb.txt'))
            self.assertEqual(rgb2[0][1], 'rgb/6.png')
            self.assertEqual(len(read_list(os.path.join(dsts[0], 'depth.txt'))), 8)
            gt2 = os.path.join(dsts[1], 'groundtruth.txt')
            self.assertFalse(os.path.islink(gt2))
            with open(gt2) as f:
                self.assertIn('0.123456789', f.read(), 'ground-truth lines copied unchanged')
            self.assertEqual(len(read_poses(gt2)), 15)  # 1.5 .. 2.2 s at 20 Hz
            for name in ('rgb', 'depth', 'accelerometer.txt'):
                self.assertTrue(os.path.islink(os.path.join(dsts[0], name)), name)
            again = subprocess.run(['/usr/bin/python3', SCRIPT, src] + dsts, capture_output=True, text=True)
            self.assertNotEqual(again.returncode, 0)
            self.assertIn('exists', again.stderr)
            forced = subprocess.run(['/usr/bin/python3', SCRIPT, src] + dsts + ['--force'], capture_output=True, text=True)
            self.assertEqual(forced.returncode, 0, forced.stderr)
            self.assertIn('part 2 of 2', forced.stdout)
            missing = subprocess.run(['/usr/bin/python3', SCRIPT, os.path.join(d, 'none'), dsts[0] + 'x', dsts[1] + 'x'],
                                     capture_output=True, text=True)
            self.assertNotEqual(missing.returncode, 0)
            self.assertIn('not found', missing.stderr)
            one = subprocess.run(['/usr/bin/python3', SCRIPT, src, dsts[0] + 'y'], capture_output=True, text=True)
            self.assertNotEqual(one.returncode, 0)
            self.assertIn('at least two', one.stderr)
            os.remove(os.path.join(src, 'groundtruth.txt'))
            no_gt = subprocess.run(['/usr/bin/python3', SCRIPT, src, dsts[0] + 'z', dsts[1] + 'z'],
                                   capture_output=True, text=True)
            self.assertNotEqual(no_gt.returncode, 0)
            self.assertIn('groundtruth.txt', no_gt.stderr)
            self.assertFalse(os.path.exists(dsts[0] + 'z'))


if __name__ == '__main__':
    unittest.main()
