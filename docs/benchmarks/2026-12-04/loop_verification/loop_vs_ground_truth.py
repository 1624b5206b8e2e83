#!/usr/bin/env python3
"""For each closed loop in a log written with EDGE_SLAM_DEBUG_LOOP=1 (its "[loop-debug]" line:
the poses at verification), against the ground truth (TUM format):
  map drift       - the two KeyFrames' relative pose in the map before the loop vs the truth;
  loop transform  - the verified relative pose (what the correction applies) vs the truth;
  RANSAC          - the same for the 3-D RANSAC start alone.
A loop corrects the map only when its transform error is below the drift.
usage: .venv/bin/python3 loop_vs_ground_truth.py <groundtruth.txt> <launch.log or eval.log>..."""
import sys, re, numpy as np
from scipy.spatial.transform import Rotation as R

def T(v):
    M = np.eye(4); M[:3, :3] = R.from_quat(v[3:7]).as_matrix(); M[:3, 3] = v[:3]; return M

def load_gt(path):
    rows = [list(map(float, l.split())) for l in open(path) if l.strip() and not l.startswith('#')]
    return sorted((r[0], T(np.array(r[1:8]))) for r in rows)

import bisect
def at(gt, t):
    ts = [g[0] for g in gt]; i = bisect.bisect_left(ts, t)
    best = min((j for j in (i - 1, i) if 0 <= j < len(ts)), key=lambda j: abs(ts[j] - t))
    assert abs(ts[best] - t) < 0.02, (t, ts[best]); return gt[best][1]

def err(A, B):
    D = np.linalg.inv(A) @ B
    return np.linalg.norm(D[:3, 3]) * 100, np.degrees(np.linalg.norm(R.from_matrix(D[:3, :3]).as_rotvec()))

gt = load_gt(sys.argv[1])
for log in sys.argv[2:]:
    for line in open(log, errors='replace'):
        if '[loop-debug]' not in line: continue
        s = line.split('[loop-debug]')[1].replace('\x1b[0m', '')
        parts = s.split('|'); a, b, c = parts[:3]
        a = a.split(); b = b.split(); c = list(map(float, c.split()[:7]))
        cur_id, cur_t, cur = a[0], float(a[1]), T(np.array(list(map(float, a[2:9]))))
        loop_id, loop_t, lp = b[0], float(b[1]), T(np.array(list(map(float, b[2:9]))))
        corr = T(np.array(c))
        g1, g2 = at(gt, cur_t), at(gt, loop_t)
        rel_true = np.linalg.inv(g1) @ g2
        drift = err(np.linalg.inv(cur) @ lp, rel_true)
        loopw = err(np.linalg.inv(corr) @ lp, rel_true)
        ransac = err(np.linalg.inv(T(np.array(list(map(float, parts[3].split()[:7]))))) @ lp, rel_true) if len(parts) > 3 else (float('nan'),)*2
        dist = np.linalg.norm(rel_true[:3, 3]) * 100
        print(f"{log.split('/')[-2]:14s} KF {cur_id}<->{loop_id} apart {dist:5.1f} cm | map drift {drift[0]:5.2f} cm {drift[1]:4.2f} deg | loop transform error {loopw[0]:5.2f} cm {loopw[1]:4.2f} deg | RANSAC {ransac[0]:5.2f} cm {ransac[1]:4.2f} deg")
