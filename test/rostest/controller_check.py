#!/usr/bin/python3
"""rostest: the map-update controller (paper 4.7.2). Updates disabled through the service from
the first tracked frame: none is accepted while disabled and the counters blame the controller;
re-enabled: updates are accepted again."""
import sys
import time
import unittest

import rospy
import rostest

from split_test_support import PLAYER, SplitSystem, node_running


def update_counters(status):
    """The mobile's update counters (received, accepted, refused by rule) as one line."""
    return ', '.join('%s %d' % (k, getattr(status, k)) for k in (
        'received', 'accepted', 'rejected_controller', 'rejected_initializing', 'rejected_redundant',
        'rejected_keyframe_rate', 'rejected_not_lost', 'rejected_invalid'))


class ControllerTest(unittest.TestCase):
    def test_disable_then_enable_updates(self):
        system = SplitSystem()
        system.wait_for_tracking()
        reply = system.set_updates(False)
        self.assertTrue(reply.success, reply.message)
        self.assertFalse(reply.enabled)
        self.assertEqual(system.mobile_status().accepted, 0, 'disabled before any update could be applied')

        # Two updates reach the mobile while disabled (counted by the mobile itself: an update the
        # edge has sent may still be in flight). The bag is 30 s and the edge sends one every 5 s
        # of data time, so about three remain for the re-enabled phase.
        disabled = system.wait_until(lambda: (lambda s: s if s.received >= 2 else None)(system.mobile_status()),
                                     90, 'two updates to reach the mobile while disabled')
        print('while disabled: received %d accepted %d rejected_controller %d' % (
            disabled.received, disabled.accepted, disabled.rejected_controller), file=sys.stderr)
        self.assertFalse(disabled.enabled)
        self.assertEqual(disabled.accepted, 0)
        self.assertGreaterEqual(disabled.rejected_controller, 2)
        self.assertEqual(disabled.rejected_controller + disabled.rejected_invalid, disabled.received,
                         'every update (periodic or relocalization) refused by rule (a), the controller')

        reply = system.set_updates(True)
        self.assertTrue(reply.enabled)
        accepted = system.wait_until(lambda: system.mobile_status().accepted, 90, 'an update accepted after re-enabling',
                                     detail=lambda: 'mobile %s; edge sent %d; player running %s' % (
                                         update_counters(system.mobile_status()), system.edge_status().updates_sent,
                                         node_running(PLAYER)))
        after = system.mobile_status()
        print('after re-enabling: accepted %d, rejected_controller %d' % (accepted, after.rejected_controller),
              file=sys.stderr)
        self.assertGreaterEqual(accepted, 1)
        self.assertTrue(after.enabled)


if __name__ == '__main__':
    rospy.init_node('controller_check')
    rostest.rosrun('edge_slam_tests', 'controller', ControllerTest)
