#!/usr/bin/env python3
"""Final trajectory of a split run, made the way ORB-SLAM2 saves its own: every frame the mobile
tracked, re-anchored on the edge's final (optimised, loop-corrected) KeyFrame poses.

split_trajectory.py <mobile_anchors.txt> <edge_keyframes.txt> <out trajectory.txt>   (venv python: scipy)

mobile_anchors.txt (written by the mobile nodelet):
  F <stamp> <reference KF id> <T_ref_c>      a tracked frame relative to its reference KeyFrame
  K <KF id> <parent KF id> <T_parent_kf>     a KeyFrame relative to its parent when created
edge_keyframes.txt: <KF id> <stamp> <T_wc> for each Global-Map KeyFrame.
A reference KeyFrame the Global-Map does not hold (culled, or refused by conditions 1-2) is
reached through its parents, as ORB-SLAM2 does for culled KeyFrames. Poses: tx ty tz qx qy qz qw.
"""
import os
import sys

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'edge_slam_common', 'python'))
from edge_slam_common.tum import InputError, read_records  # noqa: E402


def pose(v):
    """4x4 T from 'tx ty tz qx qy qz qw' words."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_quat([float(a) for a in v[3:7]]).as_matrix()  # normalises
    T[:3, 3] = np.array(v[0:3], float)
    return T


def quaternion(R):
    """x, y, z, w of a rotation matrix."""
    return tuple(Rotation.from_matrix(R).as_quat())


def read_lines(path, tag_lengths):
    try:
        return read_records(path, tag_lengths)
    except InputError as e:
        sys.exit('split_trajectory.py: %s' % e)


def final_trajectory(anchors_path, keyframes_path):
    """[(stamp, 4x4 T_wc)] for every anchored frame whose KeyFrame chain reaches the Global-Map."""
    world = {}
    for n, v in read_lines(keyframes_path, {None: 9}):  # id stamp tx ty tz qx qy qz qw
        world[int(v[0])] = pose(v[2:9])
    parent = {}
    frames = []
    for n, v in read_lines(anchors_path, {'F': 10, 'K': 10}):
        if v[0] == 'K':
            parent[int(v[1])] = (int(v[2]), pose(v[3:10]))
        else:
            frames.append((float(v[1]), int(v[2]), pose(v[3:10])))

    def kf_world(kf_id, depth=0):
        if kf_id in world:
            return world[kf_id]
        if kf_id not in parent or depth > 10000:
            return None
        pid, T_pk = parent[kf_id]
        T_wp = kf_world(pid, depth + 1)
        if T_wp is None:
            return None
        world[kf_id] = T_wp @ T_pk  # memoised: chains are walked once
        return world[kf_id]

    out, missing = [], 0
    for stamp, ref, T_rc in frames:
        T_wr = kf_world(ref)
        if T_wr is None:
            missing += 1
            continue
        out.append((stamp, T_wr @ T_rc))
    return out, missing, len(frames)


def main():
    if len(sys.argv) == 2 and sys.argv[1] in ('-h', '--help'):
        print('usage: ' + __doc__.split('\n\n')[1] + '\n\n' + __doc__)
        return
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    poses, missing, total = final_trajectory(sys.argv[1], sys.argv[2])
    if not poses:
        sys.exit('split_trajectory.py: no frame could be anchored on the Global-Map')
    with open(sys.argv[3], 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw (T_wc, final: frames on the edge\'s final KeyFrames)\n')
        for stamp, T in poses:
            x, y, z, w = quaternion(T[:3, :3])
            t = T[:3, 3]
            f.write('%.6f %.7f %.7f %.7f %.7f %.7f %.7f %.7f\n' % (stamp, t[0], t[1], t[2], x, y, z, w))
    print('split_trajectory.py: %d of %d frames anchored on the Global-Map (%d without a KeyFrame chain to it)'
          % (len(poses), total, missing), file=sys.stderr)


if __name__ == '__main__':
    main()
