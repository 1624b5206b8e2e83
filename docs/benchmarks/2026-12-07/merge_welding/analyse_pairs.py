# One line per run of the welding pairs (README.md, runs.txt). Usage, with the project's venv (evo):
#   PYTHONPATH=scripts .venv/bin/python3 analyse_pairs.py <folder holding the runs r<i>_weld, r<i>_noweld>
import json, sys, re, glob, os, numpy as np
from bench.ate import aligned  # evo: association and SE(3) alignment, as the bench's figures


def max_step(run, robot):
    """Largest online step error of a robot over the whole run (cm) and when (s from its start):
    |online step - ground-truth step| between consecutive frames, after one SE(3) alignment."""
    ref, est = aligned(f'{run}/{robot}/groundtruth.txt', f'{run}/{robot}/trajectory_online.txt')
    e = np.linalg.norm(np.diff(est.positions_xyz, axis=0) - np.diff(ref.positions_xyz, axis=0), axis=1)
    k = int(np.argmax(e))
    return 100 * e[k], est.timestamps[k + 1] - est.timestamps[0]


for run in sorted(glob.glob(os.path.join(sys.argv[1], 'r*_*'))):
    if not os.path.isdir(run) or not os.path.exists(f'{run}/metrics.json'): continue
    m = json.load(open(f'{run}/metrics.json'))
    log = open(f'{run}/launch.log', errors='ignore').read()
    w = re.findall(r'merge welded: (\d+) KFs free, (\d+) fixed.*?cost ([\d.e+-]+) -> ([\d.e+-]+).*?, (\d+) ms', log)
    rob = m['robots']
    steps = [max_step(run, r) for r in ('robot1', 'robot2')]
    name = os.path.basename(run)
    print(f"{name:12s} combined {100*m['ate_rmse_m']:.2f}  online {100*rob['robot1']['ate_online_rmse_m']:.2f} / {100*rob['robot2']['ate_online_rmse_m']:.2f}"
          f"  maxstep {steps[0][0]:.1f}@{steps[0][1]:.1f}s / {steps[1][0]:.1f}@{steps[1][1]:.1f}s  merges {m['merges']} loops {m['loops_closed']}"
          f"  lost {rob['robot1']['times_lost']}/{rob['robot2']['times_lost']}  weld {w[0] if w else '-'}")
