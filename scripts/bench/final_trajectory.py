"""The final trajectory of a split run: edge_slam_common's compose_trajectory tool (the one
trajectory composer, data/trajectory_anchors.h), run on the mobile's anchors and the edge's
KeyFrames, and its output read back. The tool is found in the workspace next to the other
binaries (.ws/devel/lib/edge_slam_common), or at $EDGE_SLAM_COMPOSE_TRAJECTORY.
"""
import json
import os
import subprocess
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", ".."))


def tool():
    return os.environ.get("EDGE_SLAM_COMPOSE_TRAJECTORY",
                          os.path.join(ROOT, ".ws", "devel", "lib", "edge_slam_common", "compose_trajectory"))


def compose(anchors, keyframes, out):
    """Writes the final trajectory (TUM) to `out`; returns the tool's counts {frames, anchored,
    unanchored}. RuntimeError with the tool's message when it fails (bad files, nothing anchored)."""
    r = subprocess.run([tool(), "--anchors", anchors, "--keyframes", keyframes, "--out", out, "--json"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(r.stderr.strip() or f"compose_trajectory exited with {r.returncode}")
    return json.loads(r.stdout)


def final_trajectory(anchors, keyframes):
    """([(stamp, [tx ty tz qx qy qz qw])], frames without a KeyFrame chain to the Global-Map,
    frames anchored in all), for the tests and benchmarks that check a split run."""
    from edge_slam_common.tum import read_poses, stamp_seconds
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "trajectory.txt")
        counts = compose(anchors, keyframes, path)
        poses = [(stamp_seconds(s), values) for s, values, _ in read_poses(path)]
    return poses, counts["unanchored"], counts["frames"]
