# The split runs' online step error at each installed update (bench.ate.largest_update_jump, as make eval) beside the
# monolithic runs' own step error at the same stamps (no update there): which steps the update causes.
# Reads the run folders of run_pairs.sh (/tmp/ab/tum_fr1_rpy/{on,off,mono}_N).
import glob, json, os, sys
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '../../../..'))
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
from bench.ate import largest_update_jump
GT = os.path.join(ROOT, '../shared/datasets/tum_fr1_rpy/groundtruth.txt')
monos = sorted(glob.glob('/tmp/ab/tum_fr1_rpy/mono_*/'))
t0 = 1305031229.528748
for s in sorted(glob.glob('/tmp/ab/tum_fr1_rpy/o*_*/')):
    m = json.load(open(s + 'metrics.json'))
    stamps = [t for t, _ in m['update_jumps']]
    rows = []
    for k, (t, j) in enumerate(m['update_jumps']):
        mono = []
        for mm in monos:
            _, per = largest_update_jump(GT, mm + 'trajectory_online.txt', [t])
            mono.append(per[0][1] if per else float('nan'))
        rows.append(f"{t - t0:4.1f}s {j*100:.2f} [mono {min(mono)*100:.2f}-{max(mono)*100:.2f}]")
    print(s.split('/')[-2], ' | '.join(rows))
