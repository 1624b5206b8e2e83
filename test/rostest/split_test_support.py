"""Shared by the split rostests (run by the venv python: evo): service proxies for the mobile and
edge nodelets, the mobile's trajectory from its odometry topic, the end of the bag (the player node
gone), waits on counters and topics instead of sleeps, and the ATE against ground truth (bench.ate)."""
import os
import sys
import time

import rosgraph
import rospy
from edge_slam_msgs.msg import Stats
from edge_slam_msgs.srv import GetDeliveryStatus, GetEdgeStatus, GetMapUpdateStatus, SetMapUpdates
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from std_srvs.srv import SetBool, Trigger

NS = '/edge_slam'
PLAYER = '/player'  # rosbag play / tum_player in launch/edge_slam.launch


def repo_root():
    root = rospy.get_param('~repo')
    if os.path.join(root, 'scripts') not in sys.path:
        sys.path.insert(0, os.path.join(root, 'scripts'))
    return root


def node_running(name):
    """Whether node `name` is registered with the master (publishes, subscribes or serves)."""
    state = rosgraph.Master(rospy.get_name()).getSystemState()
    return any(name in nodes for kind in state for _, nodes in kind)


class SplitSystem:
    """Talks to a running mobile + edge pair (launch/edge_slam.launch). With several robots
    (edge_slam.launch robots:=N) one SplitSystem per robot, `robot` its namespace ('robot1', ...)."""

    def __init__(self, robot=None):
        mobile = ('/%s%s' % (robot, NS) if robot else NS) + '/mobile'
        self.poses = []            # (stamp, x, y, z, qx, qy, qz, qw) from the mobile's odometry
        self.last_pose_wall = None
        self.local_map_max = 0     # largest local_map_keyframes seen on the mobile's stats topic
        self.stats_seen = 0
        rospy.Subscriber(mobile + '/odometry', Odometry, self._on_odometry, queue_size=100)
        rospy.Subscriber(mobile + '/stats', Stats, self._on_stats, queue_size=10)
        # The mobile publishes ~state once for every camera frame it deals with (tracked, lost or
        # refused by tracking): the count is how the tests know it is idle.
        self.frames_dealt_with = 0
        rospy.Subscriber(mobile + '/state', String, self._on_state, queue_size=100)
        for name in ('/map_update_status', '/set_map_updates', '/reset', '/delivery_status'):
            rospy.wait_for_service(mobile + name, timeout=120)
        # The edge's ~status is robot 0's; with several robots each has its own in its namespace.
        edge = '/%s%s/edge_status' % (robot, NS) if robot else NS + '/edge/status'
        rospy.wait_for_service(edge, timeout=120)
        self.delivery_status = rospy.ServiceProxy(mobile + '/delivery_status', GetDeliveryStatus)
        self.mobile_status = rospy.ServiceProxy(mobile + '/map_update_status', GetMapUpdateStatus)
        self.set_updates = rospy.ServiceProxy(mobile + '/set_map_updates', SetMapUpdates)
        self.reset = rospy.ServiceProxy(mobile + '/reset', Trigger)
        self.edge_status = rospy.ServiceProxy(edge, GetEdgeStatus)  # this robot's counters and ids

    def _on_odometry(self, msg):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.poses.append((msg.header.stamp.to_sec(), p.x, p.y, p.z, q.x, q.y, q.z, q.w))
        self.last_pose_wall = time.time()

    def _on_state(self, _msg):
        self.frames_dealt_with += 1

    def _on_stats(self, msg):
        values = dict(zip(msg.names, msg.values))
        self.local_map_max = max(self.local_map_max, int(values.get('local_map_keyframes', 0)))
        self.stats_seen += 1

    def wait_until(self, condition, timeout, what, detail=None):
        """Polls `condition` (wall clock); returns its last value or fails with `what` (and what
        detail() says then: the counters that tell why)."""
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            value = condition()
            if value:
                return value
            time.sleep(0.2)
        raise AssertionError('timed out after %.0f s waiting for %s%s' % (
            timeout, what, '; %s' % detail() if detail else ''))

    def wait_for_tracking(self, timeout=120):
        """The mobile answers status calls once it tracks its first frame."""
        def ready():
            try:
                self.mobile_status()
                return True
            except rospy.ServiceException:
                return False
        self.wait_until(ready, timeout, 'the mobile to start tracking')

    def wait_for_bag_end(self, timeout=300):
        """The bag is over when its player has played it and exited (its node is gone from the
        master); a mobile that stopped tracking does not look like the end."""
        self.wait_until(lambda: node_running(PLAYER), 60, 'the player node')
        self.wait_until(lambda: not node_running(PLAYER), timeout, 'the player to finish the bag')

    def wait_for_keyframes_delivered(self, timeout=60):
        """Every KeyFrame the mobile made so far has reached the edge (in its received ids)."""
        def delivered():
            made = set(self.delivery_status().created_ids)
            return made <= set(self.edge_status().received_ids)
        self.wait_until(delivered, timeout, 'every KeyFrame the mobile made to reach the edge')

    def wait_for_frame_tracked(self, stamp, timeout=20):
        """The mobile has tracked the camera frame stamped `stamp` (s): its pose is on the odometry
        topic. For a frame the test itself sent."""
        self.wait_until(lambda: any(abs(p[0] - stamp) < 1e-6 for p in self.poses[-50:]), timeout,
                        'the mobile to track the frame stamped %.6f' % stamp)

    def wait_for_pipeline_drained(self, timeout=60):
        """With the player paused: the mobile has dealt with every camera frame in flight (no ~state
        and no pose for 2 s) and the KeyFrames it made have reached the edge.
        Not "the newest frame the player sent has a pose": that frame may never come (rosbag play
        can pause between a frame's camera_info and its image; under load the short image queues
        drop frames) or come without a pose (tracking lost), and a frame sent just before the pause
        may arrive after the newest one seen (two subscribers, no order between them)."""
        repo_root()
        from bench.ros_util import wait_until_steady
        if not wait_until_steady(lambda: (self.frames_dealt_with, len(self.poses)), 2.0, timeout):
            raise AssertionError('the mobile kept dealing with camera frames %.0f s after the player paused' % timeout)
        self.wait_for_keyframes_delivered(timeout)

    def wait_for_edge_settled(self, timeout=120):
        """Local-Mapping and Loop-Closing finish what they were given: the Global-Map stops changing
        (the status offers no idle flag, so: unchanged for 4 s)."""
        repo_root()  # scripts/ on the path: the bench package
        from bench.ros_util import edge_settled_key, wait_until_steady
        if not wait_until_steady(lambda: edge_settled_key(self.edge_status()), 4.0, timeout):
            raise AssertionError('timed out after %.0f s waiting for the edge to settle' % timeout)

    def wait_for_run_files(self, out, timeout=30):
        """The nodelets' files in `out` hold every published pose (but the mobile's unflushed tail)
        and the Global-Map the edge reports now."""
        repo_root()
        from bench.bench_data import split_files_complete
        ids = list(self.edge_status().global_map_ids)
        self.wait_until(lambda: split_files_complete(out, [p[0] for p in self.poses], ids), timeout,
                        'the anchors and Global-Map KeyFrame files in %s to be complete' % out)

    def pause_player(self, pause):
        """rosbag play's own pause service (std_srvs/SetBool)."""
        import rosservice
        names = [n for n in rosservice.get_service_list() if n.endswith('pause_playback')]
        if not names:
            raise AssertionError('rosbag play offers no pause_playback service')
        rospy.ServiceProxy(names[0], SetBool)(pause)


def ate_rmse(poses, groundtruth_path):
    """ATE RMSE (metres) and pairs of (stamp, x, y, z[, qx, qy, qz, qw]) poses against the ground
    truth, from bench.ate (evo, the project's one ATE tool and association tolerance)."""
    repo_root()
    from bench import ate
    poses = sorted(poses)
    quat = [p[4:8] for p in poses] if all(len(p) == 8 for p in poses) else None
    try:
        res = ate.ate_stats(groundtruth_path, ate.trajectory([p[0] for p in poses], [p[1:4] for p in poses], quat))
    except ValueError as e:
        raise AssertionError(str(e))
    return res['ate_rmse_m'], res['ate_pairs']
