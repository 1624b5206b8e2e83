#!/usr/bin/python3
"""Cut a TUM-format folder into consecutive parts, one per robot of a multi-robot run: part k
holds the k-th stretch of the colour frames, the depth frames of the same stretch and the ground
truth over its time span, so robot 2 starts mid-sequence.

usage: split_dataset.py <src TUM folder> <dst part 1> <dst part 2> [<dst part 3> ...]
                        [--overlap N] [--force] [--json]

The colour frames are divided into as many equal stretches as destinations are given (the
first ones take one frame more when it does not divide); --overlap N extends every part but the
last by N colour frames into the next one (a place both robots saw, for the edge's map merge).
Stamps are kept as recorded: part 2's first frame is at its time in the sequence (see
scripts/eval_multi.sh for how a multi-robot run plays parts of different start times at once).
rgb.txt, depth.txt and groundtruth.txt are rewritten with the part's entries; the images and
everything else are symlinks to the source, so all parts' ground truths are in the source's one
frame. Each part is made next to its destination and renamed into place when complete. It is
derived from the dataset: keep it in results/cache or /tmp, never commit it. Keep 'fr1' in the
names of freiburg1 parts so `make eval` picks the fr1 calibration.
--json prints [{"dst", "colour", "depth", "groundtruth", "first_stamp", "last_stamp"}] per part.
"""
import argparse
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'edge_slam_common', 'python'))
from edge_slam_common.tum import InputError, read_list, read_poses, stamp_seconds  # noqa: E402
from subsample_dataset import write_list  # noqa: E402

GT_MARGIN = 0.1  # s of ground truth kept before the first and after the last colour frame of a part


def ranges(n_frames, n_parts, overlap):
    """[(first, end)] colour-frame index ranges (end exclusive) of n_parts consecutive parts."""
    if n_parts < 2:
        raise ValueError('give at least two destination folders')
    if overlap < 0:
        raise ValueError('--overlap must be >= 0')
    if n_frames < 2 * n_parts:
        raise ValueError('%d colour frames cannot make %d parts of at least 2 frames' % (n_frames, n_parts))
    size, extra = divmod(n_frames, n_parts)
    out, first = [], 0
    for k in range(n_parts):
        end = first + size + (1 if k < extra else 0)
        out.append((first, min(n_frames, end + overlap) if k < n_parts - 1 else end))
        first = end
    return out


def split(rgb, depth, gt, n_parts, overlap=0):
    """[(colour entries, depth entries, ground-truth poses)] of each part. A part keeps every depth
    frame of its span (from half-way to the colour frame before it to half-way to the one after
    it), so each part replays exactly what the sequence had then."""
    if not rgb or not depth:
        raise ValueError('rgb.txt and depth.txt must list frames')
    colour_stamps = [stamp_seconds(c[0]) for c in rgb]
    parts = []
    for first, end in ranges(len(rgb), n_parts, overlap):
        colour = rgb[first:end]
        lo = (colour_stamps[first - 1] + colour_stamps[first]) / 2 if first > 0 else float('-inf')
        hi = (colour_stamps[end - 1] + colour_stamps[end]) / 2 if end < len(rgb) else float('inf')
        t0, t1 = colour_stamps[first] - GT_MARGIN, colour_stamps[end - 1] + GT_MARGIN
        parts.append((colour, [d for d in depth if lo <= stamp_seconds(d[0]) < hi],
                      [p for p in gt if t0 <= stamp_seconds(p[0]) <= t1]))
    return parts


def write_poses(path, header, source_lines, poses):
    """The kept poses as their source lines, unchanged (no precision lost)."""
    with open(path, 'w') as f:
        f.write(header)
        for _, _, number in poses:
            f.write(source_lines[number - 1].strip() + '\n')


def make_parts(src, dsts, overlap, force):
    real_src = os.path.realpath(src)
    if not os.path.isdir(src):
        raise InputError('%s: TUM folder not found' % src)
    if len(set(os.path.realpath(d) for d in dsts)) != len(dsts):
        raise ValueError('the destination folders must differ')
    for dst in dsts:
        if os.path.realpath(dst) == real_src:
            raise ValueError('a destination is the source folder')
        if os.path.lexists(dst) and not force:
            raise ValueError("'%s' exists (use --force to replace it)" % dst)
    rgb = read_list(os.path.join(src, 'rgb.txt'))
    depth = read_list(os.path.join(src, 'depth.txt'))
    gt_path = os.path.join(src, 'groundtruth.txt')
    if not os.path.isfile(gt_path):
        raise InputError('%s: missing (each part needs its ground truth)' % gt_path)
    gt = read_poses(gt_path, normalize=False)
    with open(gt_path) as f:
        gt_lines = f.read().splitlines()
    parts = split(rgb, depth, gt, len(dsts), overlap)
    report = []
    for k, (dst, (colour, depths, poses)) in enumerate(zip(dsts, parts), 1):
        tmp = dst + '.tmp'
        shutil.rmtree(tmp, ignore_errors=True)
        os.makedirs(tmp)
        for name in os.listdir(src):
            if name not in ('rgb.txt', 'depth.txt', 'groundtruth.txt'):
                os.symlink(os.path.realpath(os.path.join(src, name)), os.path.join(tmp, name))
        note = ('# part %d of %d (overlap %d frames) cut by scripts/split_dataset.py from %s\n'
                % (k, len(dsts), overlap, real_src))
        write_list(os.path.join(tmp, 'rgb.txt'), '# color images\n' + note + '# timestamp filename\n', colour)
        write_list(os.path.join(tmp, 'depth.txt'), '# depth maps\n' + note + '# timestamp filename\n', depths)
        write_poses(os.path.join(tmp, 'groundtruth.txt'), '# ground truth trajectory\n' + note +
                    '# timestamp tx ty tz qx qy qz qw\n', gt_lines, poses)
        if os.path.lexists(dst):
            shutil.rmtree(dst)
        os.rename(tmp, dst)
        report.append({'dst': dst, 'colour': len(colour), 'depth': len(depths), 'groundtruth': len(poses),
                       'first_stamp': stamp_seconds(colour[0][0]), 'last_stamp': stamp_seconds(colour[-1][0])})
    return report


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('src')
    ap.add_argument('dst', nargs='+', help='one folder per part (at least two)')
    ap.add_argument('--overlap', type=int, default=0, help='colour frames each part shares with the next (default 0)')
    ap.add_argument('--force', action='store_true', help='replace destinations that exist')
    ap.add_argument('--json', action='store_true', help='print the result as JSON')
    a = ap.parse_args()
    try:
        report = make_parts(a.src, a.dst, a.overlap, a.force)
    except (InputError, ValueError, OSError) as e:
        sys.exit('split_dataset.py: %s' % e)
    if a.json:
        print(json.dumps(report))
    else:
        for k, r in enumerate(report, 1):
            print('%s: part %d of %d of %s: %d colour, %d depth frames, %d poses, %.3f-%.3f s'
                  % (r['dst'], k, len(report), a.src, r['colour'], r['depth'], r['groundtruth'],
                     r['first_stamp'], r['last_stamp']))


if __name__ == '__main__':
    main()
