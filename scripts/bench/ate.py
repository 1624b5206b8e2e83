"""Absolute trajectory error with evo's API: the one ATE tool behind every figure of the project
(`make eval` final and online ATE, `make bench`, the rostests and the delivery tests).

python3 -m bench.ate <groundtruth.txt> <trajectory.txt> [--json] [--update-stamps-from mobile_stats.csv]
(venv python: evo). Equivalent to `evo_ape tum <groundtruth> <trajectory> -a`: each estimated
pose paired with the nearest ground-truth stamp within MAX_DIFF (evo's nearest-time association),
SE(3) Umeyama alignment without scale, translation error statistics. With --update-stamps-from,
also the largest jump of the trajectory at a Local-Map update (largest_update_jump).
"""
import argparse
import json
import sys

import numpy as np

MAX_DIFF = 0.01  # s: evo_ape's default association tolerance, used for every ATE of the project


def trajectory(stamps, xyz, quat_xyzw=None):
    """An evo PoseTrajectory3D from arrays (orientation identity when not given: the
    translation ATE and the alignment use positions only)."""
    from evo.core.trajectory import PoseTrajectory3D
    xyz = np.asarray(xyz, float).reshape(-1, 3)
    if quat_xyzw is None:
        wxyz = np.tile([1.0, 0.0, 0.0, 0.0], (len(xyz), 1))
    else:
        wxyz = np.roll(np.asarray(quat_xyzw, float).reshape(-1, 4), 1, axis=1)
    order = np.argsort(np.asarray(stamps, float), kind="stable")
    return PoseTrajectory3D(positions_xyz=xyz[order], orientations_quat_wxyz=wxyz[order],
                            timestamps=np.asarray(stamps, float)[order])


def load(path_or_traj):
    """A TUM file path (read by evo) or an evo trajectory, returned as is."""
    if isinstance(path_or_traj, str):
        from evo.tools import file_interface
        return file_interface.read_tum_trajectory_file(path_or_traj)
    return path_or_traj


def associated(groundtruth, estimate, max_diff=MAX_DIFF, name=None):
    """(ref, est) copies holding only the pairs within max_diff, not aligned (inputs untouched).
    ValueError, naming `name` when given, when fewer than 3 poses pair up."""
    import copy
    from evo.core import sync
    prefix = f"{name}: " if name else ""
    ref, est = copy.deepcopy(load(groundtruth)), copy.deepcopy(load(estimate))
    try:
        ref, est = sync.associate_trajectories(ref, est, max_diff=max_diff)
    except Exception as e:  # evo's SyncException: nothing in common
        raise ValueError(f"{prefix}no poses associated within {max_diff} s: {e}")
    if est.num_poses < 3:
        raise ValueError(f"{prefix}only {est.num_poses} poses associated within {max_diff} s: cannot align")
    return ref, est


def aligned(groundtruth, estimate, max_diff=MAX_DIFF):
    """(ref, est): the associated pairs, est SE(3)-aligned to ref (copies; inputs untouched).
    ValueError when fewer than 3 poses pair up."""
    ref, est = associated(groundtruth, estimate, max_diff)
    est.align(ref, correct_scale=False)
    return ref, est


def evaluate(groundtruth, estimate, max_diff=MAX_DIFF):
    """(stats, ref, est): evo APE, translation part, after SE(3) alignment (rmse/mean/median/std/max
    in metres), with the associated ground truth and the aligned estimate (for plots)."""
    from evo.core import metrics
    ref, est = aligned(groundtruth, estimate, max_diff)
    ape = metrics.APE(metrics.PoseRelation.translation_part)
    ape.process_data((ref, est))
    s = ape.get_all_statistics()
    stats = {"ate_rmse_m": float(s["rmse"]), "ate_mean_m": float(s["mean"]), "ate_median_m": float(s["median"]),
             "ate_std_m": float(s["std"]), "ate_max_m": float(s["max"]), "ate_pairs": int(est.num_poses),
             "ate_tool": f"evo APE translation, SE(3) aligned, max_diff {max_diff} s (bench.ate)"}
    return stats, ref, est


def ate_stats(groundtruth, estimate, max_diff=MAX_DIFF):
    """The statistics of evaluate()."""
    return evaluate(groundtruth, estimate, max_diff)[0]


def largest_update_jump(groundtruth, online, update_stamps, max_diff=MAX_DIFF):
    """The largest jump of an online trajectory at a Local-Map update.

    The online trajectory is SE(3)-aligned to the ground truth as a whole; then, for each update
    stamp t, with i the last associated frame at or before t and i+1 the next one, the jump is
    |(p_est[i+1] - p_est[i]) - (p_gt[i+1] - p_gt[i])|: the online step minus the ground-truth step
    over the same frames (metres). Returns (largest jump or None without any update inside the
    trajectory, [(t, jump)] per update)."""
    ref, est = aligned(groundtruth, online, max_diff)
    t, p_est, p_gt = est.timestamps, est.positions_xyz, ref.positions_xyz
    per_update = []
    for stamp in sorted(float(s) for s in update_stamps):
        i = int(np.searchsorted(t, stamp, side="right")) - 1
        if i < 0 or i + 1 >= len(t):
            continue  # before the first or after the last frame: no step across it
        jump = np.linalg.norm((p_est[i + 1] - p_est[i]) - (p_gt[i + 1] - p_gt[i]))
        per_update.append((stamp, float(jump)))
    return (max(j for _, j in per_update) if per_update else None), per_update


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("groundtruth")
    ap.add_argument("trajectory")
    ap.add_argument("--max-diff", type=float, default=MAX_DIFF, help=f"association tolerance, s (default {MAX_DIFF})")
    ap.add_argument("--json", action="store_true", help="print a JSON object instead of text")
    ap.add_argument("--update-stamps-from", metavar="CSV",
                    help="a split run's mobile_stats.csv: also the largest jump at an applied update")
    a = ap.parse_args()
    def compute():
        res = ate_stats(a.groundtruth, a.trajectory, a.max_diff)
        if a.update_stamps_from:
            from .pipeline_stats import applied_update_stamps
            stamps = applied_update_stamps(a.update_stamps_from)
            jump, per_update = largest_update_jump(a.groundtruth, a.trajectory, stamps, a.max_diff)
            res["update_jump_max_m"] = jump
            res["update_jumps"] = [[round(t, 6), j] for t, j in per_update]
        return res
    print_result("bench.ate", compute, a.json)


def print_result(tool, compute, as_json):
    """A command-line ATE tool's ending: the figures (JSON or one `key: value` a line), or its
    error as the exit message."""
    try:
        res = compute()
    except (OSError, ValueError) as e:
        sys.exit(f"{tool}: {e}")
    except Exception as e:  # evo's own FileInterfaceException for unreadable files
        sys.exit(f"{tool}: {type(e).__name__}: {e}")
    if as_json:
        print(json.dumps(res))
    else:
        for k, v in res.items():
            print(f"{k}: {v}")


if __name__ == "__main__":
    main()
