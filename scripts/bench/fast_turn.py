#!/usr/bin/python3
"""Where a sequence turns fastest, from its ground truth (for the map-update controller run).

python3 -m bench.fast_turn <groundtruth.txt>  ->  prints "start end peak_deg_per_s" (dataset stamps, seconds)

The angular speed between ground-truth poses is smoothed over ~0.2 s; the window is the
contiguous stretch around the peak where it stays above half the peak. On the synthetic
sequence this finds the 90-degree look-away turn (t = 14.8-15.2 s after the start).
"""
import sys

import numpy as np
from edge_slam_common.tum import read_poses, stamp_seconds


def read_groundtruth(path):
    """Stamps (s) and unit quaternions x y z w."""
    poses = read_poses(path)
    return np.array([stamp_seconds(s) for s, _, _ in poses]), np.array([v[3:7] for _, v, _ in poses])


def fast_turn(path):
    t, q = read_groundtruth(path)
    dot = np.abs(np.sum(q[1:] * q[:-1], axis=1)).clip(0.0, 1.0)
    dt = np.diff(t)
    ok = dt > 1e-6
    speed = np.zeros(len(dt))
    speed[ok] = np.degrees(2.0 * np.arccos(dot[ok])) / dt[ok]
    mid = 0.5 * (t[1:] + t[:-1])
    width = max(1, int(round(0.2 / np.median(dt[ok]))))
    smooth = np.convolve(speed, np.ones(width) / width, mode="same")
    peak = int(np.argmax(smooth))
    lo = hi = peak
    while lo > 0 and smooth[lo - 1] > 0.5 * smooth[peak]:
        lo -= 1
    while hi + 1 < len(smooth) and smooth[hi + 1] > 0.5 * smooth[peak]:
        hi += 1
    return float(mid[lo]), float(mid[hi]), float(smooth[peak])


if __name__ == "__main__":
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print("usage: " + __doc__.split("\n\n")[1] + "\n\n" + __doc__)
        sys.exit(0)
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    start, end, peak = fast_turn(sys.argv[1])
    print(f"{start:.3f} {end:.3f} {peak:.1f}")
