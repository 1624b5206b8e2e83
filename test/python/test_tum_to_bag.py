#!/usr/bin/env python3
"""tum_to_bag on a tiny TUM folder built in a temp dir: topics, counts, encodings, stamps,
camera info and /tf; and bad input (one clear error, non-zero exit, no bag left behind)."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import cv2
import numpy as np
import rosbag

SCRIPT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)),
                                       '..', '..', 'edge_slam_common', 'scripts', 'tum_to_bag'))

CAMERA_YAML = """# tiny test camera
camera:
  name: tiny
  width: 32
  height: 24
  fx: 30.0
  fy: 31.0
  cx: 15.5
  cy: 11.5
  k1: 0.1
  k2: 0.0
  p1: 0.0
  p2: 0.0
  k3: 0.0
  fps: 30.0
  bf: 40.0
  th_depth: 40.0
  depth_factor: 5000.0
  rgb_encoding: rgb8
"""

RGB_STAMPS = ['1.000000', '1.033333', '1.066667']
DEPTH_STAMPS = ['1.010000', '1.040000']  # one colour frame has no depth: it is still written
GT_LINES = ['0.995 1 2 3 0 0 0 1', '1.025 1.5 2 3 0 0 0.7071068 0.7071068',
            '1.055 2 2 3 0 0 0 1', '1.085 2.5 2 3 0 0 0 1']


def write(path, text):
    with open(path, 'w') as f:
        f.write(text)


class TumToBagTest(unittest.TestCase):

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='tum_to_bag_test_')
        self.folder = os.path.join(self.tmp, 'tiny_sequence')
        os.makedirs(os.path.join(self.folder, 'rgb'))
        os.makedirs(os.path.join(self.folder, 'depth'))
        write(os.path.join(self.folder, 'rgb.txt'), '# color images\n# file: tiny\n# timestamp filename\n' +
              ''.join('%s rgb/%s.png\n' % (s, s) for s in RGB_STAMPS))
        write(os.path.join(self.folder, 'depth.txt'), '# depth maps\n# file: tiny\n# timestamp filename\n' +
              ''.join('%s depth/%s.png\n' % (s, s) for s in DEPTH_STAMPS))
        write(os.path.join(self.folder, 'groundtruth.txt'),
              '# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n' + '\n'.join(GT_LINES) + '\n')
        write(os.path.join(self.folder, 'camera.yaml'), CAMERA_YAML)
        bgr = np.zeros((24, 32, 3), np.uint8)
        bgr[:, :, 0] = 200  # blue in OpenCV's BGR: must come out as the third byte of rgb8
        for s in RGB_STAMPS:
            cv2.imwrite(os.path.join(self.folder, 'rgb', s + '.png'), bgr)
        depth = np.full((24, 32), 10000, np.uint16)  # 2 m
        depth[0, 0] = 0  # no reading
        for s in DEPTH_STAMPS:
            cv2.imwrite(os.path.join(self.folder, 'depth', s + '.png'), depth)
        self.out = os.path.join(self.tmp, 'out.bag')

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def run_tool(self, *extra, folder=None):
        return subprocess.run([sys.executable, SCRIPT, folder or self.folder, self.out] + list(extra),
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)

    def assert_fails_cleanly(self, result, *fragments):
        self.assertNotEqual(result.returncode, 0, result.stderr)
        error_lines = [l for l in result.stderr.splitlines() if 'error' in l]
        self.assertEqual(len(error_lines), 1, result.stderr)
        for fragment in fragments:
            self.assertIn(fragment, error_lines[0])
        self.assertNotIn('Traceback', result.stderr)
        self.assertFalse(os.path.exists(self.out))
        self.assertFalse(os.path.exists(self.out + '.active'))

    def test_converts_every_image_with_official_topics(self):
        result = self.run_tool()
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertFalse(os.path.exists(self.out + '.active'))
        with rosbag.Bag(self.out) as bag:
            msgs = [(topic, msg, t) for topic, msg, t in bag.read_messages()]
        by_topic = {}
        for topic, msg, t in msgs:
            by_topic.setdefault(topic, []).append((msg, t))
        self.assertEqual(len(by_topic['/camera/rgb/image_color']), 3)
        self.assertEqual(len(by_topic['/camera/rgb/camera_info']), 3)
        self.assertEqual(len(by_topic['/camera/depth/image']), 2)
        self.assertEqual(len(by_topic['/camera/depth/camera_info']), 2)
        self.assertEqual(len(by_topic['/tf']), 4)

        # Written in time order, stamped with the file timestamps (exactly, to the ns).
        times = [t.to_nsec() for _, _, t in msgs]
        self.assertEqual(times, sorted(times))
        rgb_stamps = [m.header.stamp for m, _ in by_topic['/camera/rgb/image_color']]
        self.assertEqual([(s.secs, s.nsecs) for s in rgb_stamps], [(1, 0), (1, 33333000), (1, 66667000)])

        colour, t = by_topic['/camera/rgb/image_color'][0]
        self.assertEqual(colour.header.stamp, t)
        self.assertEqual(colour.encoding, 'rgb8')
        self.assertEqual(colour.header.frame_id, 'openni_rgb_optical_frame')
        self.assertEqual((colour.width, colour.height, colour.step), (32, 24, 96))
        pixels = np.frombuffer(colour.data, np.uint8).reshape(24, 32, 3)
        self.assertEqual(tuple(pixels[5, 5]), (0, 0, 200))

        depth, _ = by_topic['/camera/depth/image'][1]
        self.assertEqual(depth.encoding, '32FC1')
        self.assertEqual(depth.header.stamp.to_sec(), 1.04)
        self.assertEqual(depth.step, 32 * 4)
        metres = np.frombuffer(depth.data, np.float32).reshape(24, 32)
        self.assertAlmostEqual(float(metres[3, 3]), 2.0, places=6)
        self.assertTrue(math.isnan(float(metres[0, 0])))  # 0 = no reading -> NaN

        info, _ = by_topic['/camera/rgb/camera_info'][0]
        self.assertEqual((info.width, info.height), (32, 24))
        self.assertEqual(list(info.K), [30.0, 0.0, 15.5, 0.0, 31.0, 11.5, 0.0, 0.0, 1.0])
        self.assertEqual(info.D[0], 0.1)
        self.assertEqual(info.header.stamp, colour.header.stamp)

        tf, t = by_topic['/tf'][1]
        self.assertEqual(len(tf.transforms), 1)
        tr = tf.transforms[0]
        self.assertEqual((tr.header.frame_id, tr.child_frame_id), ('world', 'kinect'))
        self.assertEqual(tr.header.stamp.to_nsec(), 1025000000)
        self.assertAlmostEqual(tr.transform.translation.x, 1.5)
        self.assertAlmostEqual(tr.transform.rotation.z, math.sqrt(0.5), places=6)

    def test_uncompressed_and_builtin_fr1_calibration(self):
        os.remove(os.path.join(self.folder, 'camera.yaml'))
        fr1 = os.path.join(self.tmp, 'rgbd_dataset_freiburg1_tiny')
        os.rename(self.folder, fr1)
        result = self.run_tool('--compression', 'none', folder=fr1)
        self.assertEqual(result.returncode, 0, result.stderr)
        with rosbag.Bag(self.out) as bag:
            info = next(bag.read_messages(topics=['/camera/depth/camera_info']))[1]
        self.assertAlmostEqual(info.K[0], 517.306408)
        self.assertEqual(info.distortion_model, 'plumb_bob')

    def test_time_offset_moves_every_stamp(self):
        result = self.run_tool('--time-offset', '-0.5')
        self.assertEqual(result.returncode, 0, result.stderr)
        with rosbag.Bag(self.out) as bag:
            msgs = list(bag.read_messages())
        colour = [(m, t) for topic, m, t in msgs if topic == '/camera/rgb/image_color']
        self.assertEqual([(m.header.stamp.secs, m.header.stamp.nsecs) for m, _ in colour],
                         [(0, 500000000), (0, 533333000), (0, 566667000)])
        self.assertEqual([t for _, t in colour], [m.header.stamp for m, _ in colour])
        tf = [m for topic, m, _ in msgs if topic == '/tf']
        self.assertEqual((tf[0].transforms[0].header.stamp.secs, tf[0].transforms[0].header.stamp.nsecs), (0, 495000000))
        os.remove(self.out)
        self.assert_fails_cleanly(self.run_tool('--time-offset', '-2'), 'before time zero')

    def test_malformed_rgb_line(self):
        with open(os.path.join(self.folder, 'rgb.txt'), 'a') as f:
            f.write('1.1 rgb/a.png extra-word\n')
        self.assert_fails_cleanly(self.run_tool(), 'rgb.txt:7', 'extra-word')

    def test_malformed_groundtruth_line(self):
        with open(os.path.join(self.folder, 'groundtruth.txt'), 'a') as f:
            f.write('1.1 1 2 three 0 0 0 1\n')
        self.assert_fails_cleanly(self.run_tool(), 'groundtruth.txt:7', 'three')

    def test_eight_bit_depth_is_rejected(self):
        cv2.imwrite(os.path.join(self.folder, 'depth', DEPTH_STAMPS[1] + '.png'),
                    np.zeros((24, 32), np.uint8))
        self.assert_fails_cleanly(self.run_tool(), 'depth.txt:5', '16-bit single-channel', '8-bit')

    def test_unreadable_colour_image(self):
        write(os.path.join(self.folder, 'rgb', RGB_STAMPS[2] + '.png'), 'not a png')
        self.assert_fails_cleanly(self.run_tool(), 'rgb.txt:6', 'cannot read colour image')

    def test_missing_folder(self):
        self.assert_fails_cleanly(self.run_tool(folder=os.path.join(self.tmp, 'nope')), 'nope', 'not found')

    def test_no_calibration_for_unknown_folder(self):
        os.remove(os.path.join(self.folder, 'camera.yaml'))
        self.assert_fails_cleanly(self.run_tool(), 'camera.yaml', '--camera')

    def test_existing_bag_survives_a_failed_conversion(self):
        write(self.out, 'old')
        write(os.path.join(self.folder, 'depth.txt'), 'garbage\n')
        result = self.run_tool()
        self.assertNotEqual(result.returncode, 0)
        with open(self.out) as f:
            self.assertEqual(f.read(), 'old')
        self.assertFalse(os.path.exists(self.out + '.active'))


if __name__ == '__main__':
    unittest.main()
