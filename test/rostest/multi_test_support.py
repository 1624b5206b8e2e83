"""Shared by the multi-robot rostests (launch/edge_slam.launch robots:=2 on the two-robot
synthetic sequence, started paused): one SplitSystem per robot, the players released together,
the merges heard on ~merges, and each robot's final trajectory in the world frame composed from
its anchors and the edge's KeyFrames (compose_trajectory) once the run files are complete."""
import os

import rosgraph
import rospy
from edge_slam_msgs.msg import MapMerge

from split_test_support import SplitSystem, ate_rmse, repo_root

ROBOTS = ('robot1', 'robot2')
# The poses as tracked, bounded loosely to catch a broken map (multi_robot_check.py says why).
TRACKED_BOUND_M = 0.20
DATA = {'robot1': 'bags/synthetic_room', 'robot2': 'bags/synthetic_room_robot2'}  # edge_slam.launch's bag1, bag2


class MultiRobotRun:
    """Both robots' systems (robots[name]), the merges seen, the run folder (~out)."""

    def __init__(self):
        self.root = repo_root()
        self.out = rospy.get_param('~out')
        self.merges = []
        rospy.Subscriber('/edge_slam/edge/merges', MapMerge, self.merges.append, queue_size=10)
        self.robots = {name: SplitSystem(name) for name in ROBOTS}
        self.first = self.robots[ROBOTS[0]]

    def release_players(self):
        from bench.ros_util import release_players
        release_players(list(ROBOTS), 180)

    def groundtruth(self, name):
        return os.path.join(self.root, DATA[name], 'groundtruth.txt')

    def final_trajectories(self, names, in_map):
        """For each robot of `names`: waits until its anchors and the edge's KeyFrame file hold
        what the nodelets did (`in_map`: every Global-Map KeyFrame id, all robots), composes its
        final trajectory into <out>/<robot>/trajectory.txt; returns {name: (path, counts)}."""
        from bench.bench_data import split_files_complete
        from bench.final_trajectory import compose
        keyframes = os.path.join(self.out, 'edge_keyframes.txt')
        result = {}
        for name in names:
            system, folder = self.robots[name], os.path.join(self.out, name)
            system.wait_until(lambda: split_files_complete(folder, [p[0] for p in system.poses], in_map, keyframes), 30,
                              "%s's anchors and the Global-Map KeyFrame file in %s to be complete" % (name, self.out))
            path = os.path.join(folder, 'trajectory.txt')
            result[name] = (path, compose(os.path.join(folder, 'mobile_anchors.txt'), keyframes, path))
        return result

    def online_ate(self, name):
        """(ATE RMSE m, poses matched) of the robot's poses as tracked, in its own map frame."""
        return ate_rmse(self.robots[name].poses, self.groundtruth(name))


def kill_node(name, caller='/multi_test'):
    """SIGKILL the process of ROS node `name` (a robot that dies: no clean shutdown)."""
    import signal
    import xmlrpc.client
    uri = rosgraph.Master(caller).lookupNode(name)
    code, _, pid = xmlrpc.client.ServerProxy(uri).getPid(caller)
    if code != 1:
        raise AssertionError('%s did not give its pid' % name)
    os.kill(pid, signal.SIGKILL)
    return pid
