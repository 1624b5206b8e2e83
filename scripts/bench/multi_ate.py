"""The combined ATE of a multi-robot run: every robot's final trajectory in the edge's world frame,
ONE SE(3) alignment of all of them together against all their ground truths (evo's API, as
bench.ate), so a robot map placed wrongly in the world shows as error; also each robot's share.

python3 -m bench.multi_ate --robot <name> <groundtruth.txt> <trajectory.txt> [--robot ...] [--json]
(venv python: evo). Each robot's poses are paired with its own ground truth first (evo's
nearest-time association, bench.ate.MAX_DIFF), so robots whose stamps overlap in time never pair
with each other's ground truth; the pairs of all robots are then concatenated and aligned once
(Umeyama, no scale), and the translation errors are summarised over all of them (ate_rmse_m ...)
and per robot ("robots": {name: {"ate_rmse_m", "ate_pairs"}}, in the one common alignment).
The ground truths must be in one frame (both halves of a TUM sequence are; so are the synthetic
room's robots). Exit 1 with one line on bad input or when a robot pairs fewer than 3 poses.
"""
import argparse

import numpy as np

from .ate import MAX_DIFF, associated, print_result


def combined_ate(robots, max_diff=MAX_DIFF):
    """robots: [(name, ground truth, estimate)] (paths or evo trajectories). Returns the statistics
    of one alignment of all robots' associated poses together (metres)."""
    from evo.core import metrics
    from evo.core.trajectory import PoseTrajectory3D
    if not robots:
        raise ValueError("no robot given")
    names = [r[0] for r in robots]
    if len(set(names)) != len(names):
        raise ValueError("robot names must differ")
    refs, ests, owner = [], [], []
    for name, gt, est in robots:
        r, e = associated(gt, est, max_diff, name)
        refs.append(r)
        ests.append(e)
        owner += [name] * e.num_poses

    def joined(parts):
        # Stamps are only an order here: the robots' pairs are already made, and their own
        # stamps may overlap. The k-th pose of the concatenation gets stamp k.
        xyz = np.concatenate([p.positions_xyz for p in parts])
        wxyz = np.concatenate([p.orientations_quat_wxyz for p in parts])
        return PoseTrajectory3D(positions_xyz=xyz, orientations_quat_wxyz=wxyz, timestamps=np.arange(len(xyz), dtype=float))

    ref, est = joined(refs), joined(ests)
    est.align(ref, correct_scale=False)
    ape = metrics.APE(metrics.PoseRelation.translation_part)
    ape.process_data((ref, est))
    s = ape.get_all_statistics()
    err = np.asarray(ape.error, float)
    owner = np.asarray(owner)
    per_robot = {n: {"ate_rmse_m": float(np.sqrt(np.mean(err[owner == n] ** 2))), "ate_pairs": int(np.sum(owner == n))}
                 for n in names}
    return {"ate_rmse_m": float(s["rmse"]), "ate_mean_m": float(s["mean"]), "ate_median_m": float(s["median"]),
            "ate_max_m": float(s["max"]), "ate_pairs": int(est.num_poses), "robots": per_robot,
            "ate_tool": f"evo APE translation, one SE(3) alignment of all robots, max_diff {max_diff} s (bench.multi_ate)"}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--robot", nargs=3, action="append", metavar=("NAME", "GROUNDTRUTH", "TRAJECTORY"), required=True,
                    help="a robot's name, its ground truth and its final trajectory in the world frame (repeat)")
    ap.add_argument("--max-diff", type=float, default=MAX_DIFF, help=f"association tolerance, s (default {MAX_DIFF})")
    ap.add_argument("--json", action="store_true", help="print a JSON object instead of text")
    a = ap.parse_args()
    print_result("bench.multi_ate", lambda: combined_ate([tuple(r) for r in a.robot], a.max_diff), a.json)


if __name__ == "__main__":
    main()
