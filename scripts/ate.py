#!/usr/bin/python3
"""Absolute trajectory error (fallback when evo is not installed).

ate.py <groundtruth.txt> <trajectory.txt> [--max-dt 0.02] [--json]
Both files are TUM format (stamp tx ty tz qx qy qz qw). Each estimated pose is paired
with the ground-truth pose closest in time (within max-dt, each ground-truth pose used
once), the estimate is aligned to the ground truth with the Umeyama SE(3) method (rotation
and translation, no scale, as `evo_ape tum ... -a`), and the translation errors are summarised.
"""
import argparse
import json
import sys

import numpy as np


def read_tum(path):
    stamps, xyz = [], []
    try:
        f = open(path)
    except OSError as e:
        sys.exit(f"ate.py: cannot read {path}: {e.strerror}")
    with f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith('#'):
                continue
            v = line.replace(',', ' ').split()
            if len(v) < 8:
                sys.exit(f"{path}:{n}: expected 8 values, got {len(v)}")
            stamps.append(float(v[0]))
            xyz.append([float(v[1]), float(v[2]), float(v[3])])
    if not stamps:
        sys.exit(f"{path}: no poses")
    return np.array(stamps), np.array(xyz)


def associate(t_est, t_gt, max_dt):
    """Greedy nearest-in-time pairing, closest pairs first, one-to-one."""
    idx = np.searchsorted(t_gt, t_est)
    candidates = []
    for i, j in enumerate(idx):
        for k in (j - 1, j):
            if 0 <= k < len(t_gt):
                dt = abs(t_gt[k] - t_est[i])
                if dt <= max_dt:
                    candidates.append((dt, i, k))
    candidates.sort()
    used_e, used_g, pairs = set(), set(), []
    for dt, i, k in candidates:
        if i in used_e or k in used_g:
            continue
        used_e.add(i)
        used_g.add(k)
        pairs.append((i, k))
    pairs.sort()
    return pairs


def umeyama_se3(src, dst):
    """R, t minimising sum |dst - (R src + t)|^2."""
    mu_s, mu_d = src.mean(0), dst.mean(0)
    cov = (dst - mu_d).T @ (src - mu_s) / len(src)
    U, _, Vt = np.linalg.svd(cov)
    S = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        S[2, 2] = -1
    R = U @ S @ Vt
    return R, mu_d - R @ mu_s


def ate_stats(t_est, p_est, t_gt, p_gt, max_dt=0.02):
    """Aligned translation errors of estimated positions against ground truth (arrays of stamps
    and Nx3 positions, any order), summarised; ValueError when fewer than 3 poses pair up."""
    order = np.argsort(t_gt)
    t_gt, p_gt = t_gt[order], p_gt[order]
    pairs = associate(t_est, t_gt, max_dt)
    if len(pairs) < 3:
        raise ValueError(f"only {len(pairs)} poses associated within {max_dt} s: cannot align")
    e = p_est[[i for i, _ in pairs]]
    g = p_gt[[k for _, k in pairs]]
    R, t = umeyama_se3(e, g)
    err = np.linalg.norm(g - (e @ R.T + t), axis=1)
    return {
        'ate_rmse_m': float(np.sqrt(np.mean(err ** 2))),
        'ate_mean_m': float(np.mean(err)),
        'ate_median_m': float(np.median(err)),
        'ate_std_m': float(np.std(err)),
        'ate_max_m': float(np.max(err)),
        'ate_pairs': len(pairs),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('groundtruth')
    ap.add_argument('trajectory')
    ap.add_argument('--max-dt', type=float, default=0.02)
    ap.add_argument('--json', action='store_true', help='print a JSON object instead of text')
    a = ap.parse_args()
    t_gt, p_gt = read_tum(a.groundtruth)
    t_est, p_est = read_tum(a.trajectory)
    try:
        res = ate_stats(t_est, p_est, t_gt, p_gt, a.max_dt)
    except ValueError as e:
        sys.exit(str(e))
    res['ate_tool'] = 'scripts/ate.py'
    if a.json:
        print(json.dumps(res))
    else:
        for k, v in res.items():
            print(f"{k}: {v}")


if __name__ == '__main__':
    main()
