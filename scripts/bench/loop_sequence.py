#!/usr/bin/python3
"""The long run's sequence, made in a second from the embedded one: its closed path driven
LAPS times in a row.

python3 -m bench.loop_sequence <TUM folder with a closed path> <out folder> [--laps 20] [--every 2]

The synthetic room's camera path ends exactly at its start pose (its last frame repeats the
first), so lap k is frames 0 .. n-2 with every stamp advanced by k x the path's duration: one
continuous trajectory with exact ground truth. --every 2 keeps every 2nd frame (15 fps, as
`edge_slam_synth --long`). The images are not copied: rgb/ and depth/ are symlinks to the
source folder's, so 10 minutes cost a few MB of text instead of 20 minutes of rendering.
Refuses a source whose path is not closed (first and last ground-truth poses differ by > 1 mm).
"""
import argparse
import os
import shutil
import sys

from edge_slam_common.tum import InputError, data_lines


def rows(path):
    return [words for _, _, words in data_lines(path)]


def write(path, header, lines):
    with open(path + '.tmp', 'w') as f:
        f.write(header)
        f.writelines(lines)
    os.replace(path + '.tmp', path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('source')
    ap.add_argument('out')
    ap.add_argument('--laps', type=int, default=20)
    ap.add_argument('--every', type=int, default=2)
    a = ap.parse_args()
    if a.laps < 1 or a.every < 1:
        sys.exit('loop_sequence.py: --laps and --every must be >= 1')
    src = os.path.abspath(a.source)
    try:
        rgb, depth, gt = (rows(os.path.join(src, n)) for n in ('rgb.txt', 'depth.txt', 'groundtruth.txt'))
    except InputError as e:
        sys.exit(f'loop_sequence.py: {e}')
    if not (len(rgb) == len(depth) == len(gt)) or len(rgb) < 3:
        sys.exit(f'loop_sequence.py: {src}: expected one colour, depth and pose line per frame '
                 f'(got {len(rgb)}, {len(depth)}, {len(gt)})')
    first, last = [float(v) for v in gt[0][1:4]], [float(v) for v in gt[-1][1:4]]
    if max(abs(x - y) for x, y in zip(first, last)) > 1e-3:
        sys.exit(f'loop_sequence.py: {src}: the path is not closed (first and last poses differ)')
    t0 = float(gt[0][0])
    period = float(gt[-1][0]) - t0
    keep = range(0, len(gt) - 1, a.every)  # the last frame is the next lap's first

    os.makedirs(a.out, exist_ok=True)
    for sub in ('rgb', 'depth'):
        link = os.path.join(a.out, sub)
        if os.path.islink(link) or os.path.exists(link):
            os.remove(link)
        os.symlink(os.path.join(src, sub), link)
    if os.path.isfile(os.path.join(src, 'camera.yaml')):
        shutil.copyfile(os.path.join(src, 'camera.yaml'), os.path.join(a.out, 'camera.yaml'))
    out_rgb, out_depth, out_gt = [], [], []
    for lap in range(a.laps):
        for i in keep:
            shift = lap * period
            out_rgb.append(f'{float(rgb[i][0]) + shift:.6f} {rgb[i][1]}\n')
            out_depth.append(f'{float(depth[i][0]) + shift:.6f} {depth[i][1]}\n')
            out_gt.append(f'{float(gt[i][0]) + shift:.6f} ' + ' '.join(gt[i][1:]) + '\n')
    note = f"# file: '{os.path.basename(src)}' driven {a.laps} times, every {a.every}. frame (loop_sequence.py)\n"
    write(os.path.join(a.out, 'rgb.txt'), '# color images\n' + note + '# timestamp filename\n', out_rgb)
    write(os.path.join(a.out, 'depth.txt'), '# depth maps\n' + note + '# timestamp filename\n', out_depth)
    write(os.path.join(a.out, 'groundtruth.txt'), '# ground truth trajectory\n' + note +
          '# timestamp tx ty tz qx qy qz qw\n', out_gt)
    print(f'loop_sequence.py: {a.out}: {len(out_rgb)} frames, {a.laps * period / 60:.1f} min')


if __name__ == '__main__':
    main()
