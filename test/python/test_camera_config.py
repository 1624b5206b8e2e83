#!/usr/bin/env python3
"""config/camera_synthetic.yaml parses as plain YAML (as rosparam load does) with the project's
camera key set, scalar leaves only, and the synthetic room's intrinsics."""
import os
import unittest

import yaml

CONFIG = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)),
                                       '..', '..', 'config', 'camera_synthetic.yaml'))
KEYS = {'name', 'width', 'height', 'fx', 'fy', 'cx', 'cy', 'k1', 'k2', 'p1', 'p2', 'k3', 'fps',
        'rolling_shutter_readout', 'bf', 'th_depth', 'depth_factor', 'rgb_encoding'}


class CameraConfigTest(unittest.TestCase):

    def test_synthetic_camera_config(self):
        with open(CONFIG) as f:
            doc = yaml.safe_load(f)
        self.assertEqual(list(doc.keys()), ['camera'])
        cam = doc['camera']
        self.assertEqual(set(cam.keys()), KEYS)
        for key, value in cam.items():
            self.assertIsInstance(value, (int, float, str), key)
        self.assertEqual((cam['width'], cam['height']), (640, 480))
        self.assertEqual((cam['fx'], cam['fy'], cam['cx'], cam['cy']), (525.0, 525.0, 319.5, 239.5))
        self.assertEqual([cam[k] for k in ('k1', 'k2', 'p1', 'p2', 'k3')], [0.0] * 5)
        self.assertEqual((cam['bf'], cam['th_depth'], cam['depth_factor']), (400.0, 4.0, 5000.0))
        self.assertEqual(cam['rgb_encoding'], 'rgb8')
        self.assertEqual(cam['rolling_shutter_readout'], 0.0)  # the renderer is a global shutter
        self.assertIsInstance(cam['fx'], float)


if __name__ == '__main__':
    unittest.main()
