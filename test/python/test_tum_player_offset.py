#!/usr/bin/env python3
"""tum_player --time-offset (tum_to_bag's shifted(), shared with tum_to_bag --time-offset): stamps
moved exactly (no float rounding of 1.3e9 s stamps), in both directions, and never before time
zero; a bad offset is refused by the command line."""
import importlib.machinery
import importlib.util
import os
import subprocess
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
PLAYER = os.path.join(ROOT, 'edge_slam_common', 'scripts', 'tum_player')
TUM_TO_BAG = os.path.join(ROOT, 'edge_slam_common', 'scripts', 'tum_to_bag')


def load_player():
    loader = importlib.machinery.SourceFileLoader('tum_to_bag', TUM_TO_BAG)
    spec = importlib.util.spec_from_loader('tum_to_bag', loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


class TimeOffsetTest(unittest.TestCase):
    def test_shift_is_exact_in_nanoseconds(self):
        player = load_player()
        self.assertEqual(player.shifted((1305031229, 528748000), 0), (1305031229, 528748000))
        self.assertEqual(player.shifted((1305031241, 564425000), -12035677000), (1305031229, 528748000))
        self.assertEqual(player.shifted((10, 900000000), 200000000), (11, 100000000))
        self.assertEqual(player.shifted((10, 100000000), -200000000), (9, 900000000))
        with self.assertRaises(ValueError):
            player.shifted((1, 0), -2000000000)

    def test_bad_offset_is_refused(self):
        r = subprocess.run(['/usr/bin/python3', PLAYER, '/nonexistent', '--time-offset', 'inf'],
                           capture_output=True, text=True, timeout=60)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn('--time-offset', r.stderr)


if __name__ == '__main__':
    unittest.main()
