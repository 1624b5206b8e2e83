#!/usr/bin/env python3
"""bench.ros_util players_waiting_for: a multi-robot run's paused players are resumed only once
every robot's mobile subscribes to its colour and depth topics, every player offers its pause
service and the edge's status service is up; what is missing is named."""
import os
import sys
import unittest

sys.path.insert(0, os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts')))
from bench.ros_util import players_waiting_for  # noqa: E402


def state(subscribed, services):
    return ([], [[t, ['/m']] for t in subscribed] + [['/robot2/camera/rgb/image_color', []]],
            [[s, ['/n']] for s in services])


class WaitingForTest(unittest.TestCase):
    ALL_TOPICS = ['/robot%d/camera/%s' % (k, t) for k in (1, 2) for t in ('rgb/image_color', 'depth/image')]
    ALL_SERVICES = ['/edge_slam/edge/status', '/robot1/player/pause_playback', '/robot2/player/pause_playback']

    def test_everything_up(self):
        self.assertEqual(players_waiting_for(state(self.ALL_TOPICS, self.ALL_SERVICES), ['robot1', 'robot2']), [])

    def test_missing_parts_are_named(self):
        missing = players_waiting_for(state(self.ALL_TOPICS[:2], self.ALL_SERVICES[1:2]), ['robot1', 'robot2'])
        self.assertEqual(missing, ['/edge_slam/edge/status', 'a subscriber of /robot2/camera/rgb/image_color',
                                   'a subscriber of /robot2/camera/depth/image', '/robot2/player/pause_playback'])


if __name__ == '__main__':
    unittest.main()
