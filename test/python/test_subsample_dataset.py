#!/usr/bin/env python3
"""subsample_dataset.py on a tiny TUM folder: every K-th colour frame with its nearest depth frame,
symlinks for the rest, and bad input refused with one clear error."""
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
SCRIPT = os.path.join(ROOT, 'scripts', 'subsample_dataset.py')
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
sys.path.insert(0, os.path.join(ROOT, 'edge_slam_common', 'python'))
from subsample_dataset import subsample  # noqa: E402
from edge_slam_common.tum import read_list  # noqa: E402


def entries(stamps, folder):
    return [((int(s), int(round((s - int(s)) * 1e9))), '%s/%.6f.png' % (folder, s), n) for n, s in enumerate(stamps, 1)]


class SubsampleTest(unittest.TestCase):
    def test_every_second_colour_frame_with_its_nearest_depth(self):
        rgb = entries([10.00, 10.033, 10.067, 10.100, 10.133], 'rgb')
        depth = entries([10.01, 10.040, 10.060, 10.110, 10.140, 10.170], 'depth')
        colour, depths = subsample(rgb, depth, 2)
        self.assertEqual([c[1] for c in colour], ['rgb/10.000000.png', 'rgb/10.067000.png', 'rgb/10.133000.png'])
        self.assertEqual([d[1] for d in depths], ['depth/10.010000.png', 'depth/10.060000.png', 'depth/10.140000.png'])
        self.assertEqual(subsample(rgb, depth, 1)[0], rgb)

    def test_copy_on_disk_and_bad_input(self):
        with tempfile.TemporaryDirectory() as d:
            src = os.path.join(d, 'fr1_tiny')
            os.makedirs(os.path.join(src, 'rgb'))
            os.makedirs(os.path.join(src, 'depth'))
            with open(os.path.join(src, 'rgb.txt'), 'w') as f:
                f.write('# color\n' + ''.join('%.6f rgb/%d.png\n' % (1.0 + i / 30.0, i) for i in range(10)))
            with open(os.path.join(src, 'depth.txt'), 'w') as f:
                f.write(''.join('%.6f depth/%d.png\n' % (1.005 + i / 30.0, i) for i in range(10)))
            with open(os.path.join(src, 'groundtruth.txt'), 'w') as f:
                f.write('1.0 0 0 0 0 0 0 1\n')
            dst = os.path.join(d, 'fr1_tiny_half')
            out = subprocess.run(['/usr/bin/python3', SCRIPT, src, dst, '--json'], capture_output=True, text=True)
            self.assertEqual(out.returncode, 0, out.stderr)
            self.assertIn('"colour": 5', out.stdout)
            self.assertEqual(len(read_list(os.path.join(dst, 'rgb.txt'))), 5)
            self.assertEqual(len(read_list(os.path.join(dst, 'depth.txt'))), 5)
            self.assertTrue(os.path.islink(os.path.join(dst, 'groundtruth.txt')))
            self.assertTrue(os.path.islink(os.path.join(dst, 'rgb')))
            again = subprocess.run(['/usr/bin/python3', SCRIPT, src, dst], capture_output=True, text=True)
            self.assertNotEqual(again.returncode, 0)
            self.assertIn('exists', again.stderr)
            missing = subprocess.run(['/usr/bin/python3', SCRIPT, os.path.join(d, 'none'), dst + '2'],
                                     capture_output=True, text=True)
            self.assertNotEqual(missing.returncode, 0)
            self.assertIn('rgb.txt', missing.stderr)
            zero = subprocess.run(['/usr/bin/python3', SCRIPT, src, dst + '3', '--every', '0'], capture_output=True, text=True)
            self.assertNotEqual(zero.returncode, 0)
            self.assertIn('--every', zero.stderr)


if __name__ == '__main__':
    unittest.main()
