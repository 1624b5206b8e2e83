#!/usr/bin/python3
"""Copy of a TUM-format folder with consecutive colour frames replaced by black images.

blank_frames.py <src TUM folder> <dst folder> [--start N] [--count 20] [--force]

Used to check that tracking is lost and relocalizes afterwards (issue 4). Everything
untouched is a symlink to the source (files, depth/), rgb/ becomes a real folder of symlinks
except the blanked frames, which are black images of the original size and format (so
rgb.txt stays valid). --start is the index in rgb.txt order (default: the middle frame).
The copy is meant for /tmp: never commit it (it is derived from the dataset).
"""
import argparse
import os
import shutil
import sys

import cv2
import numpy as np


def read_rgb_list(path):
    """(stamp, relative file) pairs of rgb.txt, in file order."""
    entries = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith('#'):
                continue
            parts = line.split()
            if len(parts) >= 2:
                entries.append((parts[0], parts[1]))
    return entries


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('src')
    ap.add_argument('dst')
    ap.add_argument('--start', type=int, default=None, help='first blanked frame (index in rgb.txt)')
    ap.add_argument('--count', type=int, default=20, help='number of consecutive frames blanked')
    ap.add_argument('--force', action='store_true', help='replace dst if it exists')
    a = ap.parse_args()

    src, dst = os.path.abspath(a.src), os.path.abspath(a.dst)
    rgb_txt = os.path.join(src, 'rgb.txt')
    if not os.path.isfile(rgb_txt):
        sys.exit(f"blank_frames: '{rgb_txt}' not found: not a TUM folder")
    entries = read_rgb_list(rgb_txt)
    if a.count < 1:
        sys.exit('blank_frames: --count must be >= 1')
    start = len(entries) // 2 if a.start is None else a.start
    if start < 0 or start + a.count > len(entries):
        sys.exit(f'blank_frames: frames {start}..{start + a.count - 1} outside the {len(entries)} listed in rgb.txt')
    if os.path.realpath(dst) == os.path.realpath(src):
        sys.exit('blank_frames: destination is the source folder')
    if os.path.lexists(dst):
        if not a.force:
            sys.exit(f"blank_frames: '{dst}' exists (use --force to replace it)")
        shutil.rmtree(dst)

    blanked = {entries[i][1] for i in range(start, start + a.count)}
    if any(os.path.dirname(rel) != 'rgb' for rel in blanked):
        sys.exit('blank_frames: rgb.txt names files outside rgb/: not supported')
    os.makedirs(dst)
    for name in os.listdir(src):
        if name != 'rgb':
            os.symlink(os.path.join(src, name), os.path.join(dst, name))
    os.makedirs(os.path.join(dst, 'rgb'))
    for name in os.listdir(os.path.join(src, 'rgb')):
        os.symlink(os.path.join(src, 'rgb', name), os.path.join(dst, 'rgb', name))

    for rel in sorted(blanked):
        original = cv2.imread(os.path.join(src, rel), cv2.IMREAD_UNCHANGED)
        if original is None:
            sys.exit(f"blank_frames: cannot read '{os.path.join(src, rel)}'")
        out = os.path.join(dst, rel)
        os.unlink(out)  # the symlink made above; writing through it would alter the source
        if not cv2.imwrite(out, np.zeros_like(original)):
            sys.exit(f"blank_frames: cannot write '{out}'")

    first, last = entries[start][0], entries[start + a.count - 1][0]
    print(f'blank_frames: {dst}: {a.count} colour frames blanked, indices {start}..{start + a.count - 1} '
          f'(stamps {first}..{last}), everything else symlinked to {src}')


if __name__ == '__main__':
    main()
