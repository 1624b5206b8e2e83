#!/usr/bin/python3
"""Copy of a TUM-format folder with consecutive colour frames replaced by black images.

blank_frames.py <src TUM folder> <dst folder> [--start N] [--count 20] [--force] [--json]
blank_frames.py <src TUM folder> <dst folder> --start-fraction 0.4 --seconds 1.0 [--force] [--json]

Used to check that tracking is lost and relocalizes afterwards (README, `make bench`). Blanking
the colour image (depth kept) leaves the tracker with no features. Everything untouched is a
symlink to the source (files, depth/); rgb/ becomes a real folder of symlinks except the blanked
frames, which are black images of the original size and format (so rgb.txt stays valid).
Frames are chosen by index in rgb.txt order (--start, default the middle frame; --count) or by
time (--start-fraction of the sequence, --seconds long). The copy is made next to dst and renamed
into place when complete. It is meant for /tmp: never commit it (it is derived from the dataset).
--json prints {"dst", "count", "indices": [first, last], "stamps": [first, last]} instead of text.
"""
import argparse
import json
import os
import shutil
import sys

import cv2
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'edge_slam_common', 'python'))
from edge_slam_common.tum import InputError, read_list, stamp_seconds  # noqa: E402


def blanked_indices(stamps, start=None, count=20, start_fraction=None, seconds=None):
    """Indices (in rgb.txt order) of the frames to blank: by index or, with start_fraction and
    seconds, those with t0 <= stamp < t0 + seconds, t0 at start_fraction of the sequence."""
    if start_fraction is not None:
        t0 = stamps[0] + start_fraction * (stamps[-1] - stamps[0])
        return [i for i, s in enumerate(stamps) if t0 <= s < t0 + seconds]
    if count < 1:
        raise ValueError('--count must be >= 1')
    start = len(stamps) // 2 if start is None else start
    if start < 0 or start + count > len(stamps):
        raise ValueError(f'frames {start}..{start + count - 1} outside the {len(stamps)} listed in rgb.txt')
    return list(range(start, start + count))


def make_copy(src, dst, entries, indices, force):
    """Writes the copy into dst (via dst.tmp); entries: read_list(rgb.txt)."""
    if os.path.realpath(dst) == os.path.realpath(src):
        raise ValueError('destination is the source folder')
    if os.path.lexists(dst) and not force:
        raise ValueError(f"'{dst}' exists (use --force to replace it)")
    blanked = {entries[i][1] for i in indices}
    if any(os.path.dirname(rel) != 'rgb' for rel in blanked):
        raise ValueError('rgb.txt names files outside rgb/: not supported')
    tmp = dst + '.tmp'
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for name in os.listdir(src):
        if name != 'rgb':
            os.symlink(os.path.join(src, name), os.path.join(tmp, name))
    os.makedirs(os.path.join(tmp, 'rgb'))
    for name in os.listdir(os.path.join(src, 'rgb')):
        rel = os.path.join('rgb', name)
        if rel not in blanked:
            os.symlink(os.path.join(src, rel), os.path.join(tmp, rel))
    for rel in sorted(blanked):
        original = cv2.imread(os.path.join(src, rel), cv2.IMREAD_UNCHANGED)
        if original is None:
            raise ValueError(f"cannot read '{os.path.join(src, rel)}'")
        if not cv2.imwrite(os.path.join(tmp, rel), np.zeros_like(original)):
            raise ValueError(f"cannot write '{os.path.join(tmp, rel)}'")
    if os.path.lexists(dst):
        shutil.rmtree(dst)
    os.rename(tmp, dst)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('src')
    ap.add_argument('dst')
    ap.add_argument('--start', type=int, default=None, help='first blanked frame (index in rgb.txt)')
    ap.add_argument('--count', type=int, default=20, help='number of consecutive frames blanked')
    ap.add_argument('--start-fraction', type=float, default=None, help='blank by time: where the run starts (0-1)')
    ap.add_argument('--seconds', type=float, default=1.0, help='blank by time: length of the run (s)')
    ap.add_argument('--force', action='store_true', help='replace dst if it exists')
    ap.add_argument('--json', action='store_true', help='print the blanked range as JSON')
    a = ap.parse_args()

    src, dst = os.path.abspath(a.src), os.path.abspath(a.dst)
    rgb_txt = os.path.join(src, 'rgb.txt')
    if not os.path.isfile(rgb_txt):
        sys.exit(f"blank_frames: '{rgb_txt}' not found: not a TUM folder")
    try:
        entries = read_list(rgb_txt)
        if not entries:
            raise ValueError(f'{rgb_txt} lists no images')
        stamps = [stamp_seconds(e[0]) for e in entries]
        indices = blanked_indices(stamps, a.start, a.count, a.start_fraction, a.seconds)
        if not indices:
            raise ValueError('no frame in the requested time range')
        make_copy(src, dst, entries, indices, a.force)
    except (InputError, ValueError, OSError) as e:
        sys.exit(f'blank_frames: {e}')
    first, last = indices[0], indices[-1]
    result = {'dst': dst, 'count': len(indices), 'indices': [first, last], 'stamps': [stamps[first], stamps[last]]}
    if a.json:
        print(json.dumps(result))
    else:
        print(f'blank_frames: {dst}: {len(indices)} colour frames blanked, indices {first}..{last} '
              f'(stamps {stamps[first]:.6f}..{stamps[last]:.6f}), everything else symlinked to {src}')


if __name__ == '__main__':
    main()
