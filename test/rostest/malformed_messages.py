"""Structurally invalid KeyFrame / Frame / MapUpdate messages for the validation rostest.

Each message starts as a small valid one (4 keypoints, 2 observations, 1 new point; a MapUpdate of
2 KeyFrames and 2 points) and gets one mutation that breaks a rule of the bridge's decoder
(edge_slam_common/bridge: checked deserialization, from_message, io/record_checks), so the only
correct outcome is "rejected as malformed". None of them is a rule-based rejection (a stale seq,
a duplicate KeyFrame id already in the map): those are valid messages. Raw mutations corrupt the
serialized bytes themselves (truncated, trailing bytes, an array length far beyond the buffer)."""
import functools
import io
import math
import random
import struct
import time

from edge_slam_msgs.msg import Frame, KeyFrame, MapUpdate
from genpy import Message

NO_ID = 0xFFFFFFFF
N_KP = 4
ID_BASE = 3000000000  # far from any id the real system makes, so nothing can collide


def _random_bytes(rng, n):
    return rng.getrandbits(8 * n).to_bytes(n, 'little')


def keypoint_block(kps):
    """A valid keypoint block (edge_slam/io/keypoint_coding.h) for (x, y, octave, angle, depth)
    tuples, in its plainest form: Rice parameter 16 (a y step is a zero, or a one and a zero,
    then 16 bits), x and depth in 16 bits. The receiver takes any valid block, not only the
    compact ones the C++ encoder writes; this one is only for the test's messages."""
    x_min = min((k[0] for k in kps), default=0)
    runs = []
    for k in kps:
        if runs and runs[-1][0] == k[2] and runs[-1][1] < 0xFFFF:
            runs[-1][1] += 1
        else:
            runs.append([k[2], 1])
    head = struct.pack('<BhBBH', 1, x_min, 16, 16, len(runs))
    head += b''.join(struct.pack('<BHB', octave, count, 16) for octave, count in runs)
    bits = []
    previous_y = 0
    for x, y, _, angle, depth in kps:
        step = y - previous_y
        v = 2 * step if step >= 0 else -2 * step - 1
        bits.extend([1] * (v >> 16) + [0])
        _put_bits(bits, v, 16)
        _put_bits(bits, x - x_min, 16)
        _put_bits(bits, angle, 8)
        _put_bits(bits, depth, 16)
        previous_y = y
    return head + _packed(bits)


def point_id_block(ids):
    """A valid packed id block (edge_slam/io/point_id_coding.h) in its plainest form: bases 0 and
    2^31, every offset in 31 bits."""
    bits = []
    for i in ids:
        high = i >= 1 << 31
        bits.append(int(high))
        _put_bits(bits, i - ((1 << 31) if high else 0), 31)
    return struct.pack('<BIBIB', 1, 0, 31, 1 << 31, 31) + _packed(bits)


def _put_bits(bits, value, width):
    bits.extend((value >> b) & 1 for b in range(width))


def _packed(bits):
    """Bits, least significant first in each byte; the last byte's unused bits zero."""
    bits = bits + [0] * (-len(bits) % 8)
    return bytes(sum(bits[i + b] << b for b in range(8)) for i in range(0, len(bits), 8))


# Byte offsets in a keypoint block: coding, x_bits, depth_bits, then the first run's octave,
# count and Rice parameter.
KP_CODING, KP_X_BITS, KP_DEPTH_BITS, KP_RUN_OCTAVE, KP_RUN_COUNT, KP_RUN_RICE = 0, 3, 4, 7, 8, 10


def _features(msg, rng):
    msg.camera_name = 'synthetic'
    msg.intrinsics = [525.0, 525.0, 319.5, 239.5]
    msg.bf = 40.0
    msg.th_depth = 3.0
    msg.width, msg.height = 640, 480
    msg.keypoints = keypoint_block(sorted(
        (rng.randint(0, 5000), rng.randint(0, 3800), rng.randrange(8), rng.randrange(256), rng.randint(1, 20000))
        for _ in range(N_KP)))
    msg.descriptors = _random_bytes(rng, 32 * N_KP)


def valid_keyframe(rng, kf_id):
    m = KeyFrame()
    m.version = KeyFrame.FORMAT_VERSION
    m.seq = rng.randint(1, 1 << 40)
    m.id = kf_id
    m.frame_id = kf_id
    m.created_wall = time.time()
    m.pose.orientation.w = 1.0
    m.pose.position.x = rng.uniform(-2, 2)
    _features(m, rng)
    m.obs_kp_mask = bytes([0b11])  # keypoints 0 and 1 see points (format 5) ...
    m.obs_point_id = [kf_id + 1, kf_id + 2]
    m.new_point_kp_mask = bytes([1 << 2])  # keypoint 2 made a point (format 5) ...
    m.new_point_first_id = kf_id + 3       # ... whose id is implied: new_point_id stays empty
    m.new_point_xyz = [0.1, 0.2, 1.5]
    m.parent_id = KeyFrame.NO_PARENT
    return m


def valid_frame(rng, frame_id):
    m = Frame()
    m.version = Frame.FORMAT_VERSION
    m.seq = rng.randint(1, 1 << 40)
    m.id = frame_id
    m.created_wall = time.time()
    _features(m, rng)
    return m


def valid_map_update(rng, base_id):
    m = MapUpdate()
    m.version = MapUpdate.FORMAT_VERSION
    m.kind = MapUpdate.KIND_PERIODIC
    m.seq = rng.randint(1, 1 << 40)
    a, b = valid_keyframe(rng, base_id), valid_keyframe(rng, base_id + 10)
    for kf in (a, b):  # inside an update: observations only, points travel in `points`
        kf.new_point_kp_mask, kf.new_point_first_id, kf.new_point_id, kf.new_point_xyz = b'', 0, [], []
    b.parent_id = a.id
    m.keyframes = [a, b]
    p = m.points
    p.ids = [base_id + 1, base_id + 2]
    p.positions = [0.1, 0.2, 1.5, -0.3, 0.1, 2.0]
    p.descriptors = _random_bytes(rng, 64)
    p.normals = [0.0, 0.0, -1.0, 0.0, 0.0, -1.0]
    p.distances = [0.5, 3.0, 0.5, 3.0]
    p.ref_keyframe_ids = [a.id, a.id]
    return m


def _shorter(seq):
    return seq[:-1]


# --- field mutations shared by KeyFrame and Frame (camera + packed features) -----------------
def _camera_and_features(rng):
    bad_float = [float('nan'), float('inf'), -float('inf')]
    return {
        # any version but the message's own (KeyFrame and Frame formats move independently)
        'version': lambda m: setattr(m, 'version', rng.choice([v for v in range(256) if v != m.FORMAT_VERSION])),
        'fx_zero': lambda m: m.intrinsics.__setitem__(0, 0.0),
        'fy_negative': lambda m: m.intrinsics.__setitem__(1, -rng.uniform(1, 1000)),
        'intrinsics_not_finite': lambda m: m.intrinsics.__setitem__(rng.randint(0, 3), rng.choice(bad_float)),
        'fx_huge_nan': lambda m: m.intrinsics.__setitem__(0, float('nan')),
        'size_zero': lambda m: setattr(m, rng.choice(['width', 'height']), 0),
        'size_huge': lambda m: setattr(m, rng.choice(['width', 'height']), rng.randint(8193, 65535)),
        'bf_negative': lambda m: setattr(m, 'bf', -rng.uniform(0.1, 100)),
        'th_depth_not_finite': lambda m: setattr(m, 'th_depth', rng.choice(bad_float)),
        'camera_name_long': lambda m: setattr(m, 'camera_name', 'x' * rng.randint(257, 2000)),
        'keypoints_truncated': lambda m: setattr(m, 'keypoints', m.keypoints[:-rng.randint(1, len(m.keypoints))]),
        'keypoints_trailing': lambda m: setattr(m, 'keypoints', m.keypoints + bytes([rng.randint(1, 255)])),
        'keypoint_coding': lambda m: _set_keypoint_byte(m, KP_CODING, rng.choice([0] + list(range(2, 256)))),
        'keypoint_widths': lambda m: _set_keypoint_byte(m, rng.choice([KP_X_BITS, KP_DEPTH_BITS]), rng.randint(17, 255)),
        'keypoint_rice': lambda m: _set_keypoint_byte(m, KP_RUN_RICE, rng.randint(17, 255)),
        'keypoint_count': lambda m: _set_keypoint_byte(m, KP_RUN_COUNT, m.keypoints[KP_RUN_COUNT] + rng.choice([-1, 1, 100])),
        'descriptor_length': lambda m: setattr(
            m, 'descriptors', m.descriptors[:32 * N_KP - rng.randint(1, 31)] if rng.random() < 0.5
            else m.descriptors + bytes(rng.randint(1, 31))),
        'descriptor_count': lambda m: setattr(m, 'descriptors', m.descriptors + bytes(32 * rng.randint(1, 3))),
        'octave_range': lambda m: _set_keypoint_byte(m, KP_RUN_OCTAVE, rng.randint(32, 255)),
        'too_many_keypoints': _too_many_keypoints,
    }


def _set_keypoint_byte(m, at, value):
    block = bytearray(m.keypoints)
    block[at] = value % 256
    m.keypoints = bytes(block)


def _clear_depth(m, i):
    """Keypoint i loses its depth. In the blocks _features makes (y in 0..3800 and Rice 16: a
    zero and 16 bits per y step; then x, angle, depth in 16, 8, 16 bits) a keypoint is 57 bits
    and the runs table has one entry per run of equal octaves."""
    runs = struct.unpack_from('<H', m.keypoints, 5)[0]
    block = bytearray(m.keypoints)
    first = 8 * (7 + 4 * runs) + 57 * i + 17 + 16 + 8
    for b in range(first, first + 16):
        block[b >> 3] &= ~(1 << (b & 7)) & 0xFF
    m.keypoints = bytes(block)


def _too_many_keypoints(m):
    n = 8001
    m.keypoints = keypoint_block([(0, 0, 0, 0, 0)] * n)
    m.descriptors = bytes(32 * n)


def _keyframe_only(rng):
    bad_float = [float('nan'), float('inf'), -float('inf')]

    def too_many_new_points(m):
        # More ids than any KeyFrame may carry (the mask can only name the 4 keypoints).
        n = 8001
        m.new_point_id = list(range(m.id + 100, m.id + 100 + n))
        m.new_point_xyz = [0.5] * (3 * n)

    def implied_position_without_depth(m):
        # Format 4: no positions means back-project each source keypoint; this one has no depth.
        m.new_point_xyz = []
        _clear_depth(m, 2)

    def seen_keypoint_as_source(m):
        # Keypoint 0 sees a point and is made the source of a new one too (counts consistent).
        m.new_point_kp_mask = bytes([m.new_point_kp_mask[0] | 0b1])
        m.new_point_xyz = [0.3, 0.1, 1.2] + list(m.new_point_xyz)

    def reserved_new_point_id(m):
        if rng.random() < 0.5:
            m.new_point_first_id = NO_ID  # implied ids starting at the reserved one
        else:
            m.new_point_id = [NO_ID]

    def too_many_covisibility(m):
        m.covis_ids = list(range(1, 4002))
        m.covis_weights = [1] * 4001

    return {
        'reserved_id': lambda m: setattr(m, 'id', NO_ID),
        'position_not_finite': lambda m: setattr(m.pose.position, rng.choice('xyz'), rng.choice(bad_float)),
        'position_huge': lambda m: setattr(m.pose.position, rng.choice('xyz'), rng.choice([1, -1]) * 1e9),
        'quaternion_zero': lambda m: setattr(m.pose.orientation, 'w', 0.0),
        'quaternion_not_unit': lambda m: setattr(m.pose.orientation, 'x', rng.uniform(0.5, 3.0)),
        'quaternion_nan': lambda m: setattr(m.pose.orientation, rng.choice('xyzw'), float('nan')),
        'created_wall_not_finite': lambda m: setattr(m, 'created_wall', rng.choice(bad_float)),
        'obs_mask_past_keypoints': lambda m: setattr(m, 'obs_kp_mask', bytes([m.obs_kp_mask[0] | (1 << rng.randint(N_KP, 7))])),
        'obs_mask_size': lambda m: setattr(m, 'obs_kp_mask', m.obs_kp_mask + bytes(rng.randint(1, 3))),
        'obs_size_mismatch': lambda m: m.obs_point_id.append(m.id + 50),
        'obs_reserved_point': lambda m: m.obs_point_id.__setitem__(1, NO_ID),
        'obs_duplicate_point': lambda m: m.obs_point_id.__setitem__(1, m.obs_point_id[0]),
        # format 6: the ids bit-packed instead of listed
        'obs_packed_and_listed': lambda m: setattr(m, 'obs_point_id_packed', point_id_block(m.obs_point_id)),
        'obs_packed_truncated': lambda m: (setattr(m, 'obs_point_id_packed', point_id_block(m.obs_point_id)[:-rng.randint(1, 8)]),
                                           setattr(m, 'obs_point_id', [])),
        'obs_packed_count': lambda m: (setattr(m, 'obs_point_id_packed', point_id_block(m.obs_point_id[:1])),
                                       setattr(m, 'obs_point_id', [])),
        'obs_packed_coding': lambda m: (setattr(m, 'obs_point_id_packed', bytes([rng.choice([0, 2, 255])]) + point_id_block(m.obs_point_id)[1:]),
                                        setattr(m, 'obs_point_id', [])),
        'new_point_at_seen_keypoint': seen_keypoint_as_source,
        'new_point_not_finite': lambda m: m.new_point_xyz.__setitem__(rng.randint(0, 2), rng.choice(bad_float)),
        'new_point_xyz_size': lambda m: setattr(m, 'new_point_xyz', _shorter(m.new_point_xyz)),
        'new_point_implied_without_depth': implied_position_without_depth,
        'new_point_mask_past_keypoints': lambda m: setattr(
            m, 'new_point_kp_mask', bytes([m.new_point_kp_mask[0] | (1 << rng.randint(N_KP, 7))])),
        'new_point_mask_size': lambda m: setattr(
            m, 'new_point_kp_mask', m.new_point_kp_mask + bytes(rng.randint(1, 3))),
        'new_point_ids_disagree': lambda m: setattr(m, 'new_point_id', [m.id + 3, m.id + 4]),
        'new_point_reserved_id': reserved_new_point_id,
        'new_point_duplicates_observation': lambda m: setattr(m, 'new_point_first_id', m.obs_point_id[0]),
        'covis_size_mismatch': lambda m: (m.covis_ids.append(7), None),
        'covis_self': lambda m: (m.covis_ids.append(m.id), m.covis_weights.append(3)),
        'covis_repeated': lambda m: (m.covis_ids.extend([7, 7]), m.covis_weights.extend([1, 2])),
        'own_parent': lambda m: setattr(m, 'parent_id', m.id),
        'refuted_reserved_point': lambda m: setattr(m, 'refuted_point_ids', [m.id + 60, NO_ID]),
        'refuted_repeated_point': lambda m: setattr(m, 'refuted_point_ids', [m.id + 61, m.id + 61]),
        'too_many_refuted_points': lambda m: setattr(m, 'refuted_point_ids', list(range(m.id + 100, m.id + 100 + 20001))),
        # format 5: refuted ids as a bit mask over a range
        'refuted_both_forms': lambda m: (setattr(m, 'refuted_mask', bytes([1])), setattr(m, 'refuted_point_ids', [m.id + 62])),
        'refuted_mask_reserved_point': lambda m: (setattr(m, 'refuted_first_id', NO_ID - rng.randint(0, 7)),
                                                  setattr(m, 'refuted_mask', bytes([0x80]))),
        'too_many_refuted_points_mask': lambda m: (setattr(m, 'refuted_first_id', m.id + 100),
                                                   setattr(m, 'refuted_mask', b'\xff' * 2501)),
        'too_many_new_points': too_many_new_points,
        'too_many_covisibility': too_many_covisibility,
    }


def keyframe_mutations(rng):
    d = _camera_and_features(rng)
    d.update(_keyframe_only(rng))
    return d


def frame_mutations(rng):
    return _camera_and_features(rng)


def map_update_mutations(rng):
    kf = keyframe_mutations(rng)
    embedded = [k for k in kf if not k.startswith(('new_point', 'too_many_new'))]
    bad_float = [float('nan'), float('inf')]

    def in_keyframe(m):
        name = rng.choice(embedded)
        kf[name](m.keyframes[rng.randint(0, 1)])

    many = []  # serialized once (2001 KeyFrames are slow to serialize in Python), sent as raw bytes

    def too_many_keyframes(m):
        if not many:
            for i in range(2001):
                k = KeyFrame()
                k.version, k.id, k.parent_id = KeyFrame.FORMAT_VERSION, ID_BASE + 7 + i, KeyFrame.NO_PARENT
                k.pose.orientation.w = 1.0
                k.camera_name, k.intrinsics, k.width, k.height = 'synthetic', [525.0, 525.0, 319.5, 239.5], 640, 480
                many.append(k)
            m.keyframes = list(many)
            many[:] = [serialize(m)]
        return raw_class(MapUpdate)(many[0])

    def cycle(m):
        m.keyframes[0].parent_id = m.keyframes[1].id

    points = {
        'positions': 3, 'normals': 3, 'distances': 2,
    }

    def point_array_size(m):
        name = rng.choice(list(points) + ['ids_extra', 'descriptors', 'ref_keyframe_ids'])
        p = m.points
        if name == 'ids_extra':
            p.ids.append(p.ids[0] + 100)
        elif name == 'descriptors':
            p.descriptors = p.descriptors[:-rng.randint(1, 31)]
        elif name == 'ref_keyframe_ids':
            p.ref_keyframe_ids = p.ref_keyframe_ids[:-1]
        else:
            setattr(p, name, _shorter(getattr(p, name)))

    return {
        # any version but the message's own (KeyFrame and Frame formats move independently)
        'version': lambda m: setattr(m, 'version', rng.choice([v for v in range(256) if v != m.FORMAT_VERSION])),
        'kind_unknown': lambda m: setattr(m, 'kind', rng.randint(2, 255)),
        'keyframe_invalid': in_keyframe,
        'keyframe_id_repeated': lambda m: setattr(m.keyframes[1], 'id', m.keyframes[0].id),
        'spanning_tree_cycle': cycle,
        'too_many_keyframes': too_many_keyframes,
        'point_array_size': point_array_size,
        'point_not_finite': lambda m: m.points.positions.__setitem__(rng.randint(0, 5), rng.choice(bad_float)),
        'point_normal_not_finite': lambda m: m.points.normals.__setitem__(rng.randint(0, 5), float('nan')),
        'point_normal_too_long': lambda m: m.points.normals.__setitem__(2, -5.0),
        'point_distance_order': lambda m: m.points.distances.__setitem__(0, 10.0),
        'point_distance_negative': lambda m: m.points.distances.__setitem__(2, -1.0),
        'point_position_huge': lambda m: m.points.positions.__setitem__(rng.randint(0, 5), 1e9),
        'point_reserved_id': lambda m: m.points.ids.__setitem__(0, NO_ID),
        'point_id_repeated': lambda m: m.points.ids.__setitem__(1, m.points.ids[0]),
    }


# --- raw byte payloads ------------------------------------------------------------------
def serialize(msg):
    buf = io.BytesIO()
    msg.serialize(buf)
    return buf.getvalue()


def first_array_offset(msg):
    """Byte offset of the length field of the first variable-length array the walker meets."""
    if isinstance(msg, MapUpdate):
        return 1 + 1 + 8 + 4 + 8 + 8 + 8  # ... last_keyframe_seq, then keyframes[]
    head = 1 + 8 + 4 + 4 + 8 + 8 + 1 + 56 if isinstance(msg, KeyFrame) else 1 + 8 + 4 + 8 + 8
    return head + 4 + len(msg.camera_name.encode()) + 32 + 8 + 4 + 2 + 2  # ... width, height, then keypoints[]


def raw_mutations(rng):
    def truncated(msg):
        data = serialize(msg)
        return data[:rng.randint(0, len(data) - 1)]

    def trailing(msg):
        return serialize(msg) + _random_bytes(rng, rng.randint(1, 64))

    def huge_length(msg):
        data = bytearray(serialize(msg))
        off = first_array_offset(msg)
        struct.pack_into('<I', data, off, rng.choice([0x7FFFFFFF, 0xFFFFFFFF, rng.randint(1 << 24, 1 << 31)]))
        return bytes(data)

    return {'raw_truncated': truncated, 'raw_trailing_bytes': trailing, 'raw_huge_array_length': huge_length}


@functools.lru_cache(maxsize=None)
def raw_class(base):
    """A message class of `base`'s type whose serialization is whatever bytes it was given."""
    class Raw(base):
        __slots__ = ['raw_bytes']

        def __init__(self, raw_bytes):
            base.__init__(self)
            self.raw_bytes = raw_bytes

        def serialize(self, buff):
            buff.write(self.raw_bytes)
    return Raw


class MalformedMessages:
    """Deterministic stream (fixed seed) of (topic, mutation name, message) triples."""
    TOPICS = ('keyframes', 'frames', 'map_updates')

    def __init__(self, seed=7, raw_fraction=0.15):
        self.rng = random.Random(seed)
        self.raw_fraction = raw_fraction
        self.field = {'keyframes': keyframe_mutations(self.rng), 'frames': frame_mutations(self.rng),
                      'map_updates': map_update_mutations(self.rng)}
        self.raw = raw_mutations(self.rng)
        self.raw_types = {'keyframes': raw_class(KeyFrame), 'frames': raw_class(Frame),
                          'map_updates': raw_class(MapUpdate)}
        self.count = 0

    def valid(self, topic):
        self.count += 1
        base = ID_BASE + 1000 * (self.count % 1000000)
        if topic == 'keyframes':
            return valid_keyframe(self.rng, base)
        if topic == 'frames':
            return valid_frame(self.rng, base)
        return valid_map_update(self.rng, base)

    def make(self, topic):
        msg = self.valid(topic)
        if self.rng.random() < self.raw_fraction:
            name = self.rng.choice(sorted(self.raw))
            return name, self.raw_types[topic](self.raw[name](msg))
        name = self.rng.choice(sorted(self.field[topic]))
        replaced = self.field[topic][name](msg)  # a mutation may hand back a whole new message
        return name, replaced if isinstance(replaced, Message) else msg
