#!/usr/bin/python3
"""rostest: input validation on the real nodelets (issue #7 part 4). With playback paused and both
maps built, 10,000 structurally invalid messages (KeyFrame on `keyframes`, Frame on `frames`,
MapUpdate on `map_updates`; field mutations and corrupted raw bytes, fixed seed) are published
at the nodelets: both stay alive, each topic's malformed counter (status services and ~stats)
equals exactly what was sent there, and both maps are unchanged. Then a few bad camera frames
(wrong encodings, mismatched sizes, no valid depth, a repeated stamp) are dropped and counted
per reason, and the mobile keeps tracking when playback resumes."""
import collections
import sys
import time
import unittest

import numpy as np
import rospy
import rostest
from edge_slam_msgs.msg import Frame, KeyFrame, MapUpdate, Stats
from sensor_msgs.msg import Image

from malformed_messages import MalformedMessages, valid_keyframe
from split_test_support import NS, SplitSystem

TOTAL = 10000
WINDOW = {'keyframes': 200, 'frames': 4, 'map_updates': 4}  # below each subscriber's queue: none dropped
TYPES = {'keyframes': KeyFrame, 'frames': Frame, 'map_updates': MapUpdate}
RGB_TOPIC, DEPTH_TOPIC = '/camera/rgb/image_color', '/camera/depth/image'


class LastMessages:
    """Keeps the newest message of a few topics."""

    def __init__(self):
        self.last = {}
        self.stats = {}

    def keep(self, topic, cls, **kw):
        rospy.Subscriber(topic, cls, lambda m: self.last.__setitem__(topic, m), **kw)

    def keep_stats(self, node):
        rospy.Subscriber(NS + '/%s/stats' % node, Stats,
                         lambda m: self.stats.__setitem__(node, dict(zip(m.names, m.values))), queue_size=5)


def edge_map(s):
    return (sorted(s.global_map_ids), s.global_map_keyframes, s.global_map_points, sorted(s.inserted_ids))


def mobile_map(s):
    return (sorted(s.local_map_ids), s.local_map_keyframes, s.local_map_points)


class ValidationTest(unittest.TestCase):
    def setUp(self):
        self.system = SplitSystem()
        self.seen = LastMessages()
        self.seen.keep(RGB_TOPIC, Image, queue_size=1, buff_size=1 << 24)
        self.seen.keep(DEPTH_TOPIC, Image, queue_size=1, buff_size=1 << 24)
        self.seen.keep_stats('edge')
        self.seen.keep_stats('mobile')

    def counted(self):
        e, m = self.system.edge_status(), self.system.mobile_status()
        return {'keyframes': e.malformed_keyframes, 'frames': e.malformed_frames, 'map_updates': m.rejected_invalid}

    def test_input_validation(self):
        system = self.system
        system.wait_for_tracking()
        system.wait_until(lambda: system.edge_status().global_map_keyframes >= 4, 120, 'a Global-Map of 4 KeyFrames')
        system.pause_player(True)
        system.wait_for_pipeline_drained()  # frames and KeyFrames in flight arrive
        self.assertTrue(system.set_updates(False).success)  # the edge's own updates must not change the Local-Map
        system.wait_for_edge_settled()
        edge_before, mobile_before = system.edge_status(), system.mobile_status()
        self.assertGreater(len(edge_before.global_map_ids), 0)
        self.assertGreater(mobile_before.local_map_keyframes, 0)

        self.flood()
        self.foreign_ids()
        edge_after, mobile_after = system.edge_status(), system.mobile_status()
        self.assertEqual(edge_map(edge_after), edge_map(edge_before), 'the Global-Map is unchanged')
        self.assertEqual(mobile_map(mobile_after), mobile_map(mobile_before), 'the Local-Map is unchanged')
        self.assertEqual(mobile_after.accepted, mobile_before.accepted)
        self.assertEqual(edge_after.inserted, edge_before.inserted)

        self.assertTrue(system.set_updates(True).success)
        self.bad_images()

    def flood(self):
        system = self.system
        pubs = {t: rospy.Publisher(NS + '/' + t, TYPES[t], queue_size=1000) for t in TYPES}
        system.wait_until(lambda: all(p.get_num_connections() > 0 for p in pubs.values()), 20,
                          'the nodelets to subscribe to the test publishers')
        base = self.counted()
        gen = MalformedMessages(seed=7)
        plan = [gen.rng.choice(MalformedMessages.TOPICS) for _ in range(TOTAL)]
        sent = collections.Counter()
        kinds = collections.Counter()
        done = {t: 0 for t in TYPES}
        start = time.time()
        for topic in plan:
            deadline = time.time() + 20
            while sent[topic] - done[topic] >= WINDOW[topic]:
                if time.time() > deadline:
                    raise AssertionError('%s: %d sent, only %d counted after 20 s' % (topic, sent[topic], done[topic]))
                now = self.counted()
                done = {t: now[t] - base[t] for t in TYPES}
                if sent[topic] - done[topic] >= WINDOW[topic]:
                    time.sleep(0.002)
            name, msg = gen.make(topic)
            pubs[topic].publish(msg)
            sent[topic] += 1
            kinds[name] += 1
        try:
            system.wait_until(lambda: all(self.counted()[t] - base[t] >= sent[t] for t in TYPES), 30,
                              'every malformed message to be counted')
        except AssertionError as e:
            now = self.counted()
            raise AssertionError('%s: sent %s, counted %s' % (e, dict(sent), {t: now[t] - base[t] for t in TYPES}))
        final = self.counted()
        print('sent %s in %.1f s over %d mutation kinds; counted %s' % (
            dict(sent), time.time() - start, len(kinds), {t: final[t] - base[t] for t in TYPES}), file=sys.stderr)
        for t in TYPES:
            self.assertEqual(final[t] - base[t], sent[t], 'every malformed message on %s rejected and counted' % t)
        self.assertEqual(sum(sent.values()), TOTAL)
        # The same totals on ~stats (published every second).
        names = {'keyframes': ('edge', 'keyframes_malformed'), 'frames': ('edge', 'frames_malformed'),
                 'map_updates': ('mobile', 'updates_rejected_invalid')}

        def stats_agree():
            return all(self.seen.stats.get(n, {}).get(k) == final[t] for t, (n, k) in names.items())
        system.wait_until(stats_agree, 10, '~stats to report the same malformed counts')
        # ~stats is published after the last count: nothing was counted twice in the meantime.
        self.assertEqual(self.counted(), final, 'no message counted again after the flood')

    def foreign_ids(self):
        """Well-formed KeyFrames carrying ids that are not this (single, robot 0) mobile's
        (edge_slam_common util/robot_ids.h): another robot's KeyFrame ids, ids past the last
        robot's range, and robot 0 KeyFrame ids creating another robot's points. Each is refused
        by the edge's session and counted (~stats keyframes_foreign_ids); the maps do not change
        (checked by the caller)."""
        system = self.system
        pub = rospy.Publisher(NS + '/keyframes', KeyFrame, queue_size=1000)
        system.wait_until(lambda: pub.get_num_connections() > 0, 20, 'the edge to subscribe to the test publisher')
        system.wait_until(lambda: 'keyframes_foreign_ids' in self.seen.stats.get('edge', {}), 10, 'the edge ~stats')
        before = self.seen.stats['edge']['keyframes_foreign_ids']
        gen = MalformedMessages(seed=11)
        sent = 0
        for k in range(50):
            for kf_id, point_id in (((1 << 24) + 10 * k, None),          # robot 1's KeyFrame id
                                    ((15 << 24) + 10 * k, None),         # the last robot's
                                    ((16 << 24) + 10 * k, None),         # past every robot's range
                                    (5000000 + 10 * k, (1 << 27) + k)):  # robot 0's, creating robot 1's point
                m = valid_keyframe(gen.rng, kf_id)
                if point_id is not None:
                    m.new_point_id = [point_id]
                pub.publish(m)
                sent += 1
        system.wait_until(lambda: self.seen.stats['edge']['keyframes_foreign_ids'] - before >= sent, 30,
                          'the %d KeyFrames with foreign ids to be counted' % sent)
        self.assertEqual(self.seen.stats['edge']['keyframes_foreign_ids'] - before, sent)
        print('foreign ids: %d KeyFrames refused and counted' % sent, file=sys.stderr)

    def bad_images(self):
        """Bad camera frames between two bag frames (stamps just after the last one, so the
        synchroniser sees them in order and the bag's next frame comes after all of them)."""
        system = self.system
        rgb, depth = self.seen.last[RGB_TOPIC], self.seen.last[DEPTH_TOPIC]
        before = system.mobile_status()
        poses_before = len(system.poses)
        pub_rgb = rospy.Publisher(RGB_TOPIC, Image, queue_size=10)
        pub_depth = rospy.Publisher(DEPTH_TOPIC, Image, queue_size=10)
        system.wait_until(lambda: pub_rgb.get_num_connections() > 1 and pub_depth.get_num_connections() > 1, 20,
                          'the mobile to subscribe to the test image publishers')
        t0 = rgb.header.stamp

        def image(src, stamp, encoding=None, width=None, height=None, data=None):
            m = Image()
            m.header.frame_id = src.header.frame_id
            m.header.stamp = stamp
            m.encoding = encoding or src.encoding
            m.width, m.height = width or src.width, height or src.height
            m.is_bigendian = src.is_bigendian
            m.step = len(data) // m.height if data is not None else src.step
            m.data = data if data is not None else src.data
            return m

        def half(src, stamp):  # top-left quarter, consistent step and data
            a = np.frombuffer(src.data, np.uint8).reshape(src.height, src.step)
            part = a[:src.height // 2, :src.step // 2]
            return image(src, stamp, width=src.width // 2, height=src.height // 2, data=part.tobytes())

        # Why each pair below is dropped (None: a good frame, tracked).
        reasons = ['encoding', 'encoding', 'size', 'size', 'depth', 'depth', None, 'stamp']
        so_far = collections.Counter()

        def counted():
            now = system.mobile_status()
            return {k: getattr(now, 'images_rejected_' + k) - getattr(before, 'images_rejected_' + k) for k in expected}
        expected = {'encoding': 2, 'size': 2, 'depth': 2, 'stamp': 1}
        for k, make in enumerate([
                lambda s: (image(rgb, s, encoding='rgba8'), image(depth, s)),
                lambda s: (image(rgb, s), image(depth, s, encoding='8UC1')),
                lambda s: (half(rgb, s), image(depth, s)),
                lambda s: (half(rgb, s), half(depth, s)),
                lambda s: (image(rgb, s), image(depth, s, encoding='32FC1', data=np.full(
                    (depth.height, depth.width), np.nan, np.float32).tobytes())),
                lambda s: (image(rgb, s), image(depth, s, encoding='16UC1', data=bytes(2 * depth.width * depth.height))),
                lambda s: (image(rgb, s), image(depth, s)),  # a good frame (accepted) ...
                lambda s: (image(rgb, s), image(depth, s))]):  # ... and again: repeated stamp
            stamp = t0 + rospy.Duration(0.003 * min(k + 1, 7))
            c, d = make(stamp)
            pub_rgb.publish(c)
            pub_depth.publish(d)
            # The image queues are short (2): the next pair goes out once this one is dealt with.
            if reasons[k] is None:
                system.wait_for_frame_tracked(stamp.to_sec(), 20)
            else:
                so_far[reasons[k]] += 1
                want = dict(so_far)
                system.wait_until(lambda: all(counted()[r] >= n for r, n in want.items()), 20,
                                  'camera frame %d (bad %s) to be counted' % (k, reasons[k]))
        try:
            system.wait_until(lambda: counted() == expected, 20, 'the bad camera frames to be counted')
        finally:
            print('bad camera frames counted per reason: %s' % counted(), file=sys.stderr)
        size = system.mobile_status().images_rejected_size
        system.wait_until(lambda: self.seen.stats.get('mobile', {}).get('images_rejected_size') == size, 10,
                          '~stats to report the rejected camera frames')
        system.pause_player(False)
        system.wait_until(lambda: len(system.poses) > poses_before + 30, 60, 'tracking to go on after the bad frames')


if __name__ == '__main__':
    rospy.init_node('validation_check')
    rostest.rosrun('edge_slam_tests', 'validation', ValidationTest)
