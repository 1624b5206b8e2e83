#!/usr/bin/python3
"""rostest: the map-update controller (paper 4.7.2). Updates disabled through the service from
the first tracked frame: none is accepted while disabled and the counters blame the controller;
re-enabled: updates are accepted again."""
import sys
import time
import unittest

import rospy
import rostest

from split_test_support import SplitSystem


class ControllerTest(unittest.TestCase):
    def test_disable_then_enable_updates(self):
        system = SplitSystem()
        system.wait_for_tracking()
        reply = system.set_updates(False)
        self.assertTrue(reply.success, reply.message)
        self.assertFalse(reply.enabled)
        self.assertEqual(system.mobile_status().accepted, 0, 'disabled before any update could be applied')

        # Three update periods (5 s each) of the edge while disabled.
        edge_before = system.edge_status().updates_sent
        system.wait_until(lambda: system.edge_status().updates_sent >= edge_before + 3, 60,
                          'three updates from the edge')
        disabled = system.mobile_status()
        print('while disabled: received %d accepted %d rejected_controller %d' % (
            disabled.received, disabled.accepted, disabled.rejected_controller), file=sys.stderr)
        self.assertFalse(disabled.enabled)
        self.assertGreaterEqual(disabled.received, 2)
        self.assertEqual(disabled.accepted, 0)
        self.assertGreaterEqual(disabled.rejected_controller, 2)
        self.assertEqual(disabled.rejected_controller + disabled.rejected_invalid, disabled.received,
                         'every update (periodic or relocalization) refused by rule (a), the controller')

        reply = system.set_updates(True)
        self.assertTrue(reply.enabled)
        accepted = system.wait_until(lambda: system.mobile_status().accepted, 30, 'an update accepted after re-enabling')
        after = system.mobile_status()
        print('after re-enabling: accepted %d, rejected_controller %d' % (accepted, after.rejected_controller),
              file=sys.stderr)
        self.assertGreaterEqual(accepted, 1)
        self.assertTrue(after.enabled)


if __name__ == '__main__':
    rospy.init_node('controller_check')
    rostest.rosrun('edge_slam_tests', 'controller', ControllerTest)
