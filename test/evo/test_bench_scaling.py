#!/usr/bin/env python3
"""bench.scaling's figures from a run's files (venv python): the edge's CPU % from psutil samples
of cumulative CPU seconds (the deltas over the run, other roles ignored), its peak RSS, and each
mobile's update / KeyFrame transmit latencies from the edge's metrics (per robot with several
mobiles, the one-robot fields otherwise); the table and the plot are written."""
import json
import os
import sys
import tempfile
import unittest

SCRIPTS = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts'))
sys.path.insert(0, SCRIPTS)
from bench import scaling  # noqa: E402


class ScalingTest(unittest.TestCase):
    def test_edge_usage_from_samples(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'proc.csv')
            with open(path, 'w') as f:
                f.write('t,role,pid,cpu_s,rss_kb\n')
                f.write('100.0,edge,7,2.0,102400\n100.0,mobile,8,50.0,9999999\n')
                f.write('104.0,edge,7,5.0,204800\n108.0,edge,7,8.0,153600\n')
            cpu, rss = scaling.edge_usage(path)
            self.assertAlmostEqual(cpu, 75.0)  # 6 CPU-s over 8 s
            self.assertAlmostEqual(rss, 200.0)
            self.assertEqual(scaling.edge_usage(os.path.join(d, 'missing.csv')), (None, None))

    def test_latencies_per_robot_and_for_one(self):
        many = {'robots': {'1': {'update_latency_ms': {'median': 4.0, 'p95': 9.0},
                                 'keyframe_transmit_ms': {'median': 20.0, 'p95': 40.0}},
                           '0': {'update_latency_ms': {'median': 3.0, 'p95': 8.0},
                                 'keyframe_transmit_ms': {'median': 10.0, 'p95': 30.0}}}}
        lat = scaling.latencies(many)
        self.assertEqual(list(lat), ['robot1', 'robot2'])
        self.assertEqual(lat['robot2']['update_ms'], [4.0, 9.0])
        one = scaling.latencies({'update_build_ms': {'median': 2.5, 'p95': 5.0},
                                 'keyframe_transmit_ms': {'median': 12.0, 'p95': 33.0}})
        self.assertEqual(one, {'robot1': {'update_ms': [2.5, 5.0], 'keyframe_transmit_ms': [12.0, 33.0]}})
        self.assertEqual(scaling.latencies(None), {})

    def test_table_and_plot(self):
        figures = [{'mobiles': 1, 'rate': 0.5, 'edge_cpu_percent': 60.0, 'edge_rss_peak_mb': 300.0,
                    'latency': {'robot1': {'update_ms': [2.0, 4.0], 'keyframe_transmit_ms': [10.0, 20.0]}},
                    'ate_rmse_m': None, 'merges': None},
                   {'mobiles': 2, 'rate': 0.5, 'edge_cpu_percent': 90.0, 'edge_rss_peak_mb': None,
                    'latency': {}, 'ate_rmse_m': 0.0066, 'merges': 1}]
        lines = scaling.table(figures)
        self.assertEqual(len(lines), 4)
        self.assertIn('| 1 | 60.0 | 300 | robot1 2.0 / 4.0 | robot1 10.0 / 20.0 | - | - |', lines)
        self.assertIn('| 2 | 90.0 | - | - | - | 1 | 0.66 |', lines)
        with tempfile.TemporaryDirectory() as d:
            scaling.plot(figures, os.path.join(d, 's.png'))
            self.assertGreater(os.path.getsize(os.path.join(d, 's.png')), 1000)


if __name__ == '__main__':
    unittest.main()
