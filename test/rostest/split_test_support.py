"""Shared by the split rostests: service proxies for the mobile and edge nodelets, the mobile's
trajectory from its odometry topic, the end of the bag, and the ATE against ground truth."""
import os
import sys
import time

import numpy as np
import rospy
from edge_slam_msgs.msg import Stats
from edge_slam_msgs.srv import GetEdgeStatus, GetMapUpdateStatus, SetMapUpdates
from nav_msgs.msg import Odometry
from std_srvs.srv import SetBool, Trigger

NS = '/edge_slam'


def repo_root():
    root = rospy.get_param('~repo')
    sys.path.insert(0, os.path.join(root, 'scripts'))
    return root


class SplitSystem:
    """Talks to a running mobile + edge pair (launch/edge_slam.launch)."""

    def __init__(self):
        self.poses = []            # (stamp, x, y, z) from the mobile's odometry
        self.last_pose_wall = None
        self.local_map_max = 0     # largest local_map_keyframes seen on the mobile's stats topic
        self.stats_seen = 0
        rospy.Subscriber(NS + '/mobile/odometry', Odometry, self._on_odometry, queue_size=100)
        rospy.Subscriber(NS + '/mobile/stats', Stats, self._on_stats, queue_size=10)
        for name in ('/mobile/map_update_status', '/mobile/set_map_updates', '/mobile/reset', '/edge/status'):
            rospy.wait_for_service(NS + name, timeout=120)
        self.mobile_status = rospy.ServiceProxy(NS + '/mobile/map_update_status', GetMapUpdateStatus)
        self.set_updates = rospy.ServiceProxy(NS + '/mobile/set_map_updates', SetMapUpdates)
        self.reset = rospy.ServiceProxy(NS + '/mobile/reset', Trigger)
        self.edge_status = rospy.ServiceProxy(NS + '/edge/status', GetEdgeStatus)

    def _on_odometry(self, msg):
        p = msg.pose.pose.position
        self.poses.append((msg.header.stamp.to_sec(), p.x, p.y, p.z))
        self.last_pose_wall = time.time()

    def _on_stats(self, msg):
        values = dict(zip(msg.names, msg.values))
        self.local_map_max = max(self.local_map_max, int(values.get('local_map_keyframes', 0)))
        self.stats_seen += 1

    def wait_until(self, condition, timeout, what):
        """Polls `condition` (wall clock); returns its last value or fails with `what`."""
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            value = condition()
            if value:
                return value
            time.sleep(0.2)
        raise AssertionError('timed out after %.0f s waiting for %s' % (timeout, what))

    def wait_for_tracking(self, timeout=120):
        """The mobile answers status calls once it tracks its first frame."""
        def ready():
            try:
                self.mobile_status()
                return True
            except rospy.ServiceException:
                return False
        self.wait_until(ready, timeout, 'the mobile to start tracking')

    def wait_for_bag_end(self, quiet=5.0, timeout=240):
        """The bag is over when no pose has arrived for `quiet` seconds after the first one."""
        self.wait_until(lambda: self.last_pose_wall is not None, timeout, 'the first pose')
        self.wait_until(lambda: time.time() - self.last_pose_wall > quiet, timeout, 'the end of the bag')

    def wait_for_edge_settled(self, timeout=120):
        """Local-Mapping and Loop-Closing finish what they were given: the Global-Map stops changing."""
        last = [None, time.time()]

        def settled():
            s = self.edge_status()
            key = (s.inserted, s.global_map_keyframes, s.loops_closed, tuple(s.culled_ids))
            if key != last[0]:
                last[0], last[1] = key, time.time()
            return time.time() - last[1] > 4.0
        self.wait_until(settled, timeout, 'the edge to settle')

    def pause_player(self, pause):
        """rosbag play's own pause service (std_srvs/SetBool)."""
        import rosservice
        names = [n for n in rosservice.get_service_list() if n.endswith('pause_playback')]
        if not names:
            raise AssertionError('rosbag play offers no pause_playback service')
        rospy.ServiceProxy(names[0], SetBool)(pause)


def ate_rmse(poses, groundtruth_path, max_dt=0.02):
    """Umeyama SE(3)-aligned ATE RMSE (metres) and pairs of (stamp, x, y, z) poses, via scripts/ate.py."""
    import ate
    t_gt, p_gt = ate.read_tum(groundtruth_path)
    est = np.array(sorted(poses))
    try:
        res = ate.ate_stats(est[:, 0], est[:, 1:4], t_gt, p_gt, max_dt)
    except ValueError as e:
        raise AssertionError(str(e))
    return res['ate_rmse_m'], res['ate_pairs']
