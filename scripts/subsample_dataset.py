#!/usr/bin/python3
"""Copy of a TUM-format folder at a lower frame rate: every K-th colour frame and the depth frame
nearest to each one (as the trackers associate them), so a 30 Hz sequence becomes a 15 Hz one.

subsample_dataset.py <src TUM folder> <dst folder> [--every 2] [--force] [--json]

Used for the frame-rate robustness check (README, issue #13: fr1_rpy at half rate). rgb.txt and
depth.txt are rewritten with the kept entries; images, groundtruth.txt and everything else are
symlinks to the source. The copy is made next to dst and renamed into place when complete. It is
derived from the dataset: keep it in /tmp, never commit it. Keep 'fr1' in the name of a
freiburg1 copy so `make eval` picks the fr1 calibration.
--json prints {"dst", "every", "colour", "depth"} (frames kept) instead of text.
"""
import argparse
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'edge_slam_common', 'python'))
from edge_slam_common.tum import InputError, read_list, stamp_seconds  # noqa: E402


def nearest(stamps, t):
    """Index of the stamp closest to t (stamps sorted)."""
    lo, hi = 0, len(stamps) - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if stamps[mid] < t:
            lo = mid + 1
        else:
            hi = mid
    if lo > 0 and abs(stamps[lo - 1] - t) <= abs(stamps[lo] - t):
        return lo - 1
    return lo


def subsample(rgb, depth, every):
    """Kept (rgb entries, depth entries): every `every`-th colour frame, each with its nearest depth."""
    if every < 1:
        raise ValueError('--every must be >= 1')
    if not rgb or not depth:
        raise ValueError('rgb.txt and depth.txt must list frames')
    colour = rgb[::every]
    depth_stamps = [stamp_seconds(d[0]) for d in depth]
    picked = sorted({nearest(depth_stamps, stamp_seconds(c[0])) for c in colour})
    return colour, [depth[i] for i in picked]


def write_list(path, header, entries):
    with open(path, 'w') as f:
        f.write(header)
        for (secs, nsecs), rel, _ in entries:
            f.write('%d.%06d %s\n' % (secs, nsecs // 1000, rel))


def make_copy(src, dst, every, force):
    if os.path.realpath(dst) == os.path.realpath(src):
        raise ValueError('destination is the source folder')
    if os.path.lexists(dst) and not force:
        raise ValueError("'%s' exists (use --force to replace it)" % dst)
    rgb = read_list(os.path.join(src, 'rgb.txt'))
    depth = read_list(os.path.join(src, 'depth.txt'))
    colour, depths = subsample(rgb, depth, every)
    tmp = dst + '.tmp'
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for name in os.listdir(src):
        if name not in ('rgb.txt', 'depth.txt'):
            os.symlink(os.path.realpath(os.path.join(src, name)), os.path.join(tmp, name))
    note = '# subsampled by scripts/subsample_dataset.py: 1 colour frame in %d of %s\n' % (every, os.path.realpath(src))
    write_list(os.path.join(tmp, 'rgb.txt'), '# color images\n' + note + '# timestamp filename\n', colour)
    write_list(os.path.join(tmp, 'depth.txt'), '# depth maps\n' + note + '# timestamp filename\n', depths)
    if os.path.lexists(dst):
        shutil.rmtree(dst)
    os.rename(tmp, dst)
    return len(colour), len(depths)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('src')
    ap.add_argument('dst')
    ap.add_argument('--every', type=int, default=2, help='keep every K-th colour frame (default 2: half rate)')
    ap.add_argument('--force', action='store_true', help='replace dst if it exists')
    ap.add_argument('--json', action='store_true', help='print the result as JSON')
    a = ap.parse_args()
    try:
        n_colour, n_depth = make_copy(a.src, a.dst, a.every, a.force)
    except (InputError, ValueError, OSError) as e:
        sys.exit('subsample_dataset.py: %s' % e)
    if a.json:
        print(json.dumps({'dst': a.dst, 'every': a.every, 'colour': n_colour, 'depth': n_depth}))
    else:
        print('%s: 1 colour frame in %d of %s: %d colour, %d depth frames' % (a.dst, a.every, a.src, n_colour, n_depth))


if __name__ == '__main__':
    main()
