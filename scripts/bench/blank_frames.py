#!/usr/bin/python3
"""A copy of a TUM folder with a run of black colour frames (relocalization benchmark).

blank_frames.py <TUM folder> <out folder> [--start-fraction 0.4] [--seconds 1.0]

Blanking the colour image (depth kept) leaves the tracker with no features, so it is lost for
those frames and must relocalize when the images come back, mid-motion. Every other file is
a symlink to the original, so the copy costs only the blanked images. Prints the blanked
stamp range. (Minimal stand-in until the project ships its own blank-frames tool.)
"""
import argparse
import os
import shutil
import sys

import cv2
import numpy as np


def read_list(path):
    entries = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                stamp, name = line.split()[:2]
                entries.append((float(stamp), name))
    return entries


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--start-fraction", type=float, default=0.4, help="where the blank run starts (0-1)")
    ap.add_argument("--seconds", type=float, default=1.0, help="length of the blank run")
    args = ap.parse_args()
    src, dst = os.path.abspath(args.src), args.dst
    rgb = read_list(os.path.join(src, "rgb.txt"))
    if not rgb:
        sys.exit(f"blank_frames: {src}/rgb.txt lists no images")
    t0 = rgb[0][0] + args.start_fraction * (rgb[-1][0] - rgb[0][0])
    blanked = [(s, n) for s, n in rgb if t0 <= s < t0 + args.seconds]

    tmp = dst + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(tmp)
    for entry in os.listdir(src):
        if entry != "rgb":
            os.symlink(os.path.join(src, entry), os.path.join(tmp, entry))
    os.makedirs(os.path.join(tmp, "rgb"))
    blank_names = {n for _, n in blanked}
    for _, name in rgb:
        target = os.path.join(tmp, name)
        if name in blank_names:
            shape = cv2.imread(os.path.join(src, name), cv2.IMREAD_UNCHANGED).shape
            cv2.imwrite(target, np.zeros(shape, np.uint8))
        else:
            os.symlink(os.path.join(src, name), target)
    shutil.rmtree(dst, ignore_errors=True)
    os.rename(tmp, dst)
    print(f"{len(blanked)} blank frames {blanked[0][0]:.3f}-{blanked[-1][0]:.3f}" if blanked else "0 blank frames")


if __name__ == "__main__":
    main()
