#!/usr/bin/env python3
"""The benchmark suite's measuring pieces (scripts/bench/) on small made-up inputs: the fast-turn
finder, the blank-frames copy, the /proc sampler, CPU % from cumulative CPU seconds and the
map-update pipeline figures from event CSVs."""
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
import unittest

import cv2
import numpy as np

SCRIPTS = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts'))
sys.path.insert(0, SCRIPTS)
from bench import pipeline_stats  # noqa: E402
from bench.bench_data import cpu_percent, heap_series, objects_beyond_map  # noqa: E402
from bench.fast_turn import fast_turn  # noqa: E402


def yaw_quaternion(deg):
    h = np.radians(deg) / 2
    return [0.0, 0.0, np.sin(h), np.cos(h)]


class FastTurnTest(unittest.TestCase):

    def test_finds_the_fast_yaw_window(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, 'groundtruth.txt')
            with open(path, 'w') as f:
                yaw = 0.0
                for i in range(300):  # 10 s at 30 Hz: 10 deg/s, but 200 deg/s in t = 5.0-5.5 s
                    t = i / 30.0
                    yaw += (200.0 if 5.0 <= t < 5.5 else 10.0) / 30.0
                    f.write(f"{100 + t:.6f} 0 0 0 " + " ".join(f"{v:.9f}" for v in yaw_quaternion(yaw)) + "\n")
            start, end, peak = fast_turn(path)
        self.assertAlmostEqual(start, 105.0, delta=0.2)
        self.assertAlmostEqual(end, 105.5, delta=0.2)
        self.assertAlmostEqual(peak, 200.0, delta=15.0)


class BlankFramesTest(unittest.TestCase):

    def test_blanks_one_second_and_links_the_rest(self):
        with tempfile.TemporaryDirectory() as d:
            src, dst = os.path.join(d, 'seq'), os.path.join(d, 'blank')
            os.makedirs(os.path.join(src, 'rgb'))
            with open(os.path.join(src, 'rgb.txt'), 'w') as f:
                f.write('# colour\n# file\n# timestamp filename\n')
                for i in range(50):  # 5 s at 10 Hz
                    name = f'rgb/{i}.png'
                    cv2.imwrite(os.path.join(src, name), np.full((8, 8, 3), 200, np.uint8))
                    f.write(f'{i / 10:.6f} {name}\n')
            with open(os.path.join(src, 'groundtruth.txt'), 'w') as f:
                f.write('0 0 0 0 0 0 0 1\n')
            out = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'blank_frames.py'), src, dst,
                                  '--start-fraction', '0.5', '--seconds', '1.0', '--json'],
                                 capture_output=True, text=True, check=True).stdout
            self.assertEqual(json.loads(out)['indices'], [25, 34], out)
            self.assertEqual(json.loads(out)['stamps'], [2.5, 3.4], out)
            blank = [i for i in range(50) if cv2.imread(os.path.join(dst, f'rgb/{i}.png')).max() == 0]
            self.assertEqual(blank, list(range(25, 35)))
            self.assertTrue(os.path.islink(os.path.join(dst, 'groundtruth.txt')))
            self.assertTrue(os.path.islink(os.path.join(dst, 'rgb/0.png')))

    def test_blanks_by_index_and_refuses_a_range_outside_the_sequence(self):
        with tempfile.TemporaryDirectory() as d:
            src, dst = os.path.join(d, 'seq'), os.path.join(d, 'blank')
            os.makedirs(os.path.join(src, 'rgb'))
            with open(os.path.join(src, 'rgb.txt'), 'w') as f:
                for i in range(10):
                    cv2.imwrite(os.path.join(src, f'rgb/{i}.png'), np.full((4, 4), 90, np.uint8))
                    f.write(f'{i / 10:.6f} rgb/{i}.png\n')
            tool = [sys.executable, os.path.join(SCRIPTS, 'blank_frames.py'), src, dst]
            subprocess.run(tool + ['--start', '2', '--count', '3'], capture_output=True, check=True)
            blank = [i for i in range(10) if cv2.imread(os.path.join(dst, f'rgb/{i}.png'), cv2.IMREAD_UNCHANGED).max() == 0]
            self.assertEqual(blank, [2, 3, 4])
            again = subprocess.run(tool + ['--start', '0', '--count', '1'], capture_output=True, text=True)
            self.assertNotEqual(again.returncode, 0)
            self.assertIn('exists', again.stderr)
            outside = subprocess.run(tool + ['--start', '8', '--count', '3', '--force'], capture_output=True, text=True)
            self.assertNotEqual(outside.returncode, 0)
            self.assertIn('outside the 10', outside.stderr)


class ProcSamplerTest(unittest.TestCase):

    def test_samples_a_busy_child_of_the_root(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, 'proc.csv')
            # Spins until it has used 0.6 s of CPU, however loaded the machine is (no wall-time assumption).
            busy = 'import time\nwhile time.process_time() < 0.6: pass\n'
            root = subprocess.Popen(['/bin/sh', '-c', f'{sys.executable} -c "{busy}" bench_busy_marker; true'])
            sampler = subprocess.run([sys.executable, '-m', 'bench.proc_sampler', '--root-pid', str(root.pid), '--out',
                                      out, '--hz', '20', '--role', 'busy=bench_busy_marker',
                                      '--role', 'absent=no_such_process'], timeout=30, cwd=SCRIPTS)
            root.wait()
            self.assertEqual(sampler.returncode, 0)
            with open(out) as f:
                rows = list(csv.DictReader(f))
        self.assertGreaterEqual(len(rows), 3)
        self.assertEqual({r['role'] for r in rows}, {'busy'})
        cpu = [float(r['cpu_s']) for r in rows]
        self.assertGreater(cpu[-1], 0.3)  # most of the 0.6 CPU-s (the last 50 ms may fall after the last sample)
        self.assertEqual(cpu, sorted(cpu))
        self.assertTrue(all(int(r['rss_kb']) > 0 for r in rows))


class CpuPercentTest(unittest.TestCase):

    def test_constant_load(self):
        t = np.arange(0, 10.001, 0.05)
        tc, pct = cpu_percent(t, 0.75 * t)
        self.assertEqual(len(tc), 10)
        np.testing.assert_allclose(pct, 75.0, atol=1e-6)


class HeapSeriesTest(unittest.TestCase):
    """The nodes' "heap" rows (split/memory_row.h) on proc.csv's clock, for the long run's
    live-heap slope and the map objects alive beyond each node's map."""

    @staticmethod
    def write_run(d, roles, stats_file, rows):
        """proc.csv with one sample per role at t = 1000, and `stats_file` with (wall_time, event,
        detail) rows."""
        with open(os.path.join(d, 'proc.csv'), 'w') as f:
            f.write("t,role,pid,cpu_s,rss_kb\n" + "".join("1000.0,%s,7,0.1,90000\n" % r for r in roles))
        with open(os.path.join(d, stats_file), 'w', newline='') as f:
            w = csv.writer(f)
            w.writerow(['wall_time', 'event', 'bytes', 'detail'])
            for wall, event, detail in rows:
                w.writerow([str(wall), event, '0', detail])

    def test_reads_heap_rows_on_the_sampler_clock(self):
        with tempfile.TemporaryDirectory() as d:
            self.write_run(d, ['mobile', 'edge'], 'mobile_stats.csv', [
                (1001.0, 'frame', 'path=init'),
                (1010.0, 'heap', 'in_use_kb=40960 kept_free_kb=10240 arena_kb=51200 mapped_kb=11776'),
                (1020.0, 'heap', 'in_use_kb=41984 kept_free_kb=9216 arena_kb=51200 mapped_kb=11776')])
            h = heap_series(d)
            np.testing.assert_allclose(h['t'], [10.0, 20.0])
            np.testing.assert_allclose(h['in_use_mb'], [40.0, 41.0])
            np.testing.assert_allclose(h['arena_mb'], [50.0, 50.0])
            self.assertIsNone(h['points_beyond_map'])  # rows older than the object counts
            self.assertIsNone(h['release_ms'])  # the mobile releases after updates, not per reading

    def test_map_objects_beyond_the_local_map(self):
        counts = [(50, 17000, 50, 16800), (56, 19000, 50, 17000), (50, 17100, 50, 17100)]
        with tempfile.TemporaryDirectory() as d:
            self.write_run(d, ['mobile'], 'mobile_stats.csv', [
                (1010.0 + 10 * k, 'heap', 'in_use_kb=40960 kept_free_kb=10240 arena_kb=51200 mapped_kb=11776 '
                 'keyframes_alive=%d points_alive=%d features_alive=51 local_map_keyframes=%d local_map_points=%d'
                 % c) for k, c in enumerate(counts)])
            h = heap_series(d)
            np.testing.assert_allclose(h['keyframes_beyond_map'], [0, 6, 0])
            np.testing.assert_allclose(h['points_beyond_map'], [200, 2000, 0])
            self.assertEqual(objects_beyond_map(h), "6 / 2000 (0 / 0)")

    def test_the_edge_counts_against_its_global_map(self):
        with tempfile.TemporaryDirectory() as d:
            self.write_run(d, ['edge'], 'edge_stats.csv', [
                (1010.0, 'heap', 'in_use_kb=102400 kept_free_kb=0 arena_kb=102400 mapped_kb=0 keyframes_alive=212 '
                 'points_alive=30500 features_alive=212 global_map_keyframes=200 global_map_points=30000 '
                 'release_ms=12.5')])
            h = heap_series(d, 'edge')
            np.testing.assert_allclose(h['in_use_mb'], [100.0])
            np.testing.assert_allclose(h['release_ms'], [12.5])
            self.assertEqual(objects_beyond_map(h), "12 / 500 (12 / 500)")
            self.assertIsNone(heap_series(d))  # no mobile_stats.csv in this folder

    def test_no_heap_rows_no_series(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, 'proc.csv'), 'w') as f:
                f.write("t,role,pid,cpu_s,rss_kb\n1000.0,mobile,7,0.1,90000\n")
            self.assertIsNone(heap_series(d))  # no mobile_stats.csv (a monolithic run)
            self.write_run(d, ['mobile'], 'mobile_stats.csv', [(1001.0, 'frame', 'path=init')])
            self.assertIsNone(heap_series(d))  # a run older than the readings


class PipelineStatsTest(unittest.TestCase):
    # The event CSV's columns (edge_slam_common/include/edge_slam/io/event_log.h), in a shuffled
    # order: the readers go by name, never by position.
    HEADER = ['event', 'wall_time', 'data_time', 'seq', 'bytes', 'latency_ms', 'duration_ms', 'map_keyframes',
              'frame_stamp', 'state', 'kind', 'decision', 'deferred', 'keyframes', 'points', 'detail']

    def write(self, path, rows):
        with open(path, 'w') as f:
            w = csv.DictWriter(f, fieldnames=self.HEADER, restval='-1')
            w.writeheader()
            for r in rows:
                w.writerow(r)

    def update(self, wall, data, seq, bytes, latency, rebuild, frame_stamp, decision, deferred=0, kind='periodic'):
        return dict(event='update', wall_time=wall, data_time=data, seq=seq, bytes=bytes, latency_ms=latency,
                    duration_ms=rebuild, map_keyframes=6, frame_stamp=frame_stamp, state='', kind=kind,
                    decision=decision, deferred=deferred, detail='')

    def test_figures_from_event_rows(self):
        with tempfile.TemporaryDirectory() as d:
            self.write(os.path.join(d, 'mobile_stats.csv'), [
                dict(event='frame', wall_time=10.0, data_time=1.0, seq=1, bytes=0, duration_ms=20.0, map_keyframes=3,
                     frame_stamp=1.0, state='OK', kind='', decision='', deferred=0, detail=''),
                dict(event='keyframe_sent', wall_time=10.1, data_time=1.1, seq=1, bytes=45000, state='', kind='',
                     decision='', deferred=0, detail=''),
                self.update(15.0, 6.0, 1, 400000, 30.0, 12.0, 5.95, 'accepted'),
                self.update(20.0, 11.0, 2, 400000, 40.0, -1, 10.95, 'controller'),
                self.update(25.0, 16.0, 3, 400000, 50.0, 14.0, 15.95, 'accepted'),
                # a deferred update: its arrival, then its outcome (same seq, no transfer)
                self.update(30.0, 21.0, 4, 400000, 45.0, -1, 20.95, 'deferred'),
                self.update(30.5, 21.5, 4, 0, -1, 16.0, 21.45, 'accepted', deferred=1)])
            self.write(os.path.join(d, 'edge_stats.csv'), [
                dict(event='keyframe', wall_time=10.2, data_time=1.1, seq=1, bytes=45000, latency_ms=8.0, state='',
                     kind='', decision='inserted', deferred=0, detail=''),
                dict(event='update_sent', wall_time=15.0, data_time=6.0, seq=1, bytes=400000, duration_ms=5.0,
                     state='', kind='periodic', decision='', deferred=0, keyframes=6, points=900, detail=''),
                # sent early by the divergence trigger: a Local-Map update like the timer's
                dict(event='update_sent', wall_time=20.0, data_time=11.0, seq=2, bytes=400000, duration_ms=7.0,
                     state='', kind='divergence', decision='', deferred=0, keyframes=6, points=900, detail=''),
                dict(event='update_sent', wall_time=25.0, data_time=16.0, seq=3, bytes=400000, duration_ms=9.0,
                     state='', kind='periodic', decision='', deferred=0, keyframes=6, points=900, detail=''),
                dict(event='update_sent', wall_time=26.0, data_time=17.0, seq=4, bytes=900000, duration_ms=30.0,
                     state='', kind='relocalization', decision='', deferred=0, keyframes=20, points=3000, detail='')])
            s = pipeline_stats.summarize(d)
            t, ms = pipeline_stats.tracking_series(d)
            applied = pipeline_stats.applied_update_stamps(os.path.join(d, 'mobile_stats.csv'))
        self.assertEqual(s['keyframe_transmit_ms']['median'], 8.0)
        self.assertEqual(s['update_construction_ms']['median'], 7.0)
        self.assertEqual(s['relocalization_update_construction_ms']['median'], 30.0)
        self.assertEqual((s['updates_sent'], s['updates_sent_on_divergence']), (4, 1))
        self.assertEqual(s['update_bytes']['count'], 3)
        self.assertEqual(s['update_publish_interval_s']['median'], 5.0)
        self.assertEqual(s['update_acceptance_interval_s']['median'], 7.75)  # 10 s, then 5.5 s
        self.assertEqual(s['local_map_rebuild_ms']['median'], 14.0)
        # the deferred update is one update received (not two), accepted once, deferred once
        self.assertEqual((s['updates_received'], s['updates_accepted'], s['updates_deferred']), (4, 3, 1))
        self.assertEqual(s['update_decisions'], {'periodic accepted': 3, 'periodic controller': 1})
        self.assertEqual(s['update_delivery_ms']['count'], 4)
        self.assertEqual(s['edge_keyframe_verdicts'], {'inserted': 1})
        self.assertEqual((s['frames_tracked'], s['frames_lost']), (1, 0))
        self.assertEqual(pipeline_stats.rebuild_median(s), 14.0)
        # each install at the stamp of the last frame tracked before it
        self.assertEqual(applied, [5.95, 15.95, 21.45])
        self.assertEqual(list(ms), [20.0])

    def test_no_csv_no_figures(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(pipeline_stats.summarize(d), {})
            self.assertEqual(pipeline_stats.table_rows({'split': {}}), [])


if __name__ == '__main__':
    unittest.main()
