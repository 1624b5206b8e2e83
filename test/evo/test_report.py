#!/usr/bin/env python3
"""bench.report on a made-up bench folder: the robustness section (issue #13) turns N pairs of
runs into median / worst / spread / runs above 2x the median, with PASS/MISS against the
dataset's targets, and the other sections say "not measured" for what the runs did not leave."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPTS = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts'))
sys.path.insert(0, SCRIPTS)
from bench import report  # noqa: E402

MONO = [0.0040, 0.0042, 0.0044]        # worst 0.44 cm: within 0.45
SPLIT = [0.0045, 0.0047, 0.0120]       # median 0.47 cm = 1.12x the monolithic median; 1.2 cm > 2x median
ONLINE = [0.0080, 0.0090, 0.0110]      # worst 1.1 cm: above 1.0
JUMP = [0.0010, None, 0.0030]          # one run without an installed update


class ReportTest(unittest.TestCase):

    def test_spread(self):
        s = report.spread([0.01, None, 0.03, 0.011, 0.012])
        self.assertEqual(s['runs'], 4)
        self.assertAlmostEqual(s['median'], 0.0115)
        self.assertAlmostEqual(s['worst'], 0.03)
        self.assertAlmostEqual(s['spread'], 0.02)
        self.assertEqual(s['over_2x_median'], 1)
        self.assertIsNone(report.spread([None]))

    def test_robustness_section_and_targets(self):
        with tempfile.TemporaryDirectory() as out:
            data = os.path.join(out, 'synthetic_room')
            os.makedirs(data)
            with open(os.path.join(data, 'groundtruth.txt'), 'w') as f:
                f.write('1.0 0 0 0 0 0 0 1\n')
            runs = []
            for k in range(1, 4):
                for mode, m in (('monolithic', {'ate_rmse_m': MONO[k - 1], 'times_lost': 0}),
                                ('split', {'ate_rmse_m': SPLIT[k - 1], 'ate_online_rmse_m': ONLINE[k - 1],
                                           'update_jump_max_m': JUMP[k - 1], 'times_lost': 0})):
                    variant = 'robust_%s_%d' % (mode, k)
                    os.makedirs(os.path.join(out, 'runs', 'synthetic_room', variant))
                    with open(os.path.join(out, 'runs', 'synthetic_room', variant, 'metrics.json'), 'w') as f:
                        json.dump(m, f)
                    runs.append({'variant': variant, 'mode': mode, 'exit_code': 0, 'wall_s': 60.0})
            manifest = {'machine': {}, 'datasets': [{'name': 'synthetic_room', 'path': data, 'seconds': 30.0,
                                                      'fast_turn': [15.0, 15.4], 'fast_turn_from_start': [14.0, 14.4],
                                                      'fast_turn_peak_deg_s': 200.0, 'robust_runs': 3, 'runs': runs}]}
            with open(os.path.join(out, 'manifest.json'), 'w') as f:
                json.dump(manifest, f)
            r = subprocess.run([sys.executable, '-m', 'bench.report', '--out', out], cwd=SCRIPTS,
                               capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, 'report.md')) as f:
                md = f.read()
            with open(os.path.join(out, 'bench.json')) as f:
                bench = json.load(f)
        rob = bench['datasets']['synthetic_room']['robustness']
        self.assertAlmostEqual(rob['monolithic final']['median'], 0.0042)
        self.assertAlmostEqual(rob['split final']['worst'], 0.012)
        self.assertEqual(rob['split final']['over_2x_median'], 1)
        self.assertEqual(rob['split largest jump at an update']['runs'], 2)
        verdicts = {t['target']: t['verdict'] for t in bench['targets']}
        self.assertEqual(verdicts['Every monolithic run <= 0.45 cm (synthetic_room, 3 runs)'], 'PASS')
        self.assertEqual(verdicts['Split median final ATE <= 1.2x monolithic median (synthetic_room)'], 'PASS')
        self.assertEqual(verdicts['Every split online ATE <= 1.0 cm (synthetic_room)'], 'MISS')
        self.assertEqual(verdicts['Split ATE <= 1.1x monolithic (synthetic_room)'], 'not measured')
        self.assertIn('### 8. Robustness: repeated runs (issue #13)', md)
        self.assertIn('| split final | 3 | 0.47 | 1.20 | 0.75 | 1 |', md)


if __name__ == '__main__':
    unittest.main()
