#!/usr/bin/env python3
"""The launch files' multi-robot arguments, read by roslaunch itself (--dump-params, --args; no
master needed): robots:=1 keeps the single un-namespaced mobile (no robot_index, no mobiles
list, frames map/camera); robots:=2 gives each robot its namespace, index, frames, output folder
and namespaced camera topics, the edge its mobiles list, and only the clock robot's player
publishes /clock; robots out of range are refused."""
import os
import subprocess
import unittest

import yaml

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..'))
LAUNCH = os.path.join(ROOT, 'launch', 'edge_slam.launch')
ENV = dict(os.environ, PATH='/usr/bin:/bin:' + os.environ.get('PATH', ''))


def roslaunch(*args):
    return subprocess.run(['roslaunch'] + list(args), capture_output=True, text=True, timeout=120, env=ENV)


def params(*args):
    r = roslaunch('--dump-params', LAUNCH, *args)
    if r.returncode != 0:
        raise AssertionError(r.stdout + r.stderr)
    return yaml.safe_load(r.stdout)


class MultiLaunchTest(unittest.TestCase):

    def test_one_robot_is_the_single_mobile(self):
        p = params('out:=/tmp/o')
        self.assertNotIn('/edge_slam/edge/mobiles', p)
        self.assertNotIn('/edge_slam/mobile/robot_index', p)
        self.assertEqual(p['/edge_slam/mobile/map_frame'], 'map')
        self.assertEqual(p['/edge_slam/mobile/camera_frame'], 'camera')
        self.assertEqual(p['/edge_slam/edge/map_frame'], 'map')
        self.assertEqual(p['/edge_slam/mobile/trajectory_file'], '/tmp/o/trajectory_online.txt')
        self.assertFalse(any(k.startswith('/robot') for k in p), 'no robot namespace')

    def test_two_robots(self):
        p = params('robots:=2', 'out:=/tmp/o')
        self.assertEqual(p['/edge_slam/edge/mobiles'], ['robot1', 'robot2'])
        self.assertEqual(p['/edge_slam/edge/keyframes_file'], '/tmp/o/edge_keyframes.txt')
        for k in (1, 2):
            ns = '/robot%d/edge_slam/mobile/' % k
            self.assertEqual(p[ns + 'robot_index'], k - 1)
            self.assertEqual(p[ns + 'map_frame'], 'robot%d/map' % k)
            self.assertEqual(p[ns + 'camera_frame'], 'robot%d/camera' % k)
            self.assertEqual(p[ns + 'anchors_file'], '/tmp/o/robot%d/mobile_anchors.txt' % k)
        self.assertNotIn('/edge_slam/mobile/map_frame', p)
        nodes = roslaunch('--nodes', LAUNCH, 'robots:=2').stdout.split()
        self.assertEqual(sorted(n for n in nodes if n.endswith('player')), ['/robot1/player', '/robot2/player'])

    def test_players_remap_camera_topics_and_one_publishes_the_clock(self):
        args = {}
        for k in (1, 2):
            r = roslaunch('--args', '/robot%d/player' % k, LAUNCH, 'robots:=2', 'clock_robot:=2', 'start_paused:=true')
            self.assertEqual(r.returncode, 0, r.stderr)
            args[k] = r.stdout
        self.assertNotIn('--clock', args[1])
        self.assertIn('--clock', args[2])
        for k in (1, 2):
            self.assertIn('--pause', args[k])
            self.assertIn('/camera/rgb/image_color:=/robot%d/camera/rgb/image_color' % k, args[k])
            self.assertIn('/camera/depth/image:=/robot%d/camera/depth/image' % k, args[k])
            self.assertIn('/tf:=/robot%d/groundtruth/tf' % k, args[k])

    def test_mobile_launch_robot_argument(self):
        r = roslaunch('--dump-params', os.path.join(ROOT, 'launch', 'mobile.launch'), 'robot:=robot3', 'robot_index:=2')
        p = yaml.safe_load(r.stdout)
        self.assertEqual(p['/robot3/edge_slam/mobile/robot_index'], 2)
        self.assertEqual(p['/robot3/edge_slam/mobile/map_frame'], 'robot3/map')

    def test_robots_out_of_range(self):
        r = roslaunch('--nodes', LAUNCH, 'robots:=5')
        self.assertNotEqual(r.returncode, 0)
        self.assertIn('robots_must_be_1_2_3_or_4', r.stdout + r.stderr)


if __name__ == '__main__':
    unittest.main()
