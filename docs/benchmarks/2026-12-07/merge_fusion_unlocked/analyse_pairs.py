# One line per run of run_pairs.sh, then the medians and worst of each arm (the before build's
# corrections: median and max from its metrics, when it closed more than two). Usage:
#   python3 analyse_pairs.py <out folder of run_pairs.sh>
import glob, json, os, re, statistics, sys


def run_figures(run):
    m = json.load(open(f'{run}/metrics.json'))
    e = json.load(open(f'{run}/edge_metrics.json'))
    # Per correction (loop or merge): the time under the map lock and its longest hold; the build
    # before the change held it once (longest = locked) and logged no phases.
    log = open(f'{run}/launch.log', errors='ignore').read()
    holds = [(float(a), float(b)) for a, b in re.findall(r'map locked ([\d.]+) ms, at most ([\d.]+) at a time', log)]
    if not holds:
        t = e.get('loop_correction_locked_ms', {})
        holds = [(t['max'], t['max'])] if t.get('count') == 1 else \
                [(t['median'], t['median']), (t['max'], t['max'])] if t.get('count') else []
    phases = re.findall(r'fusion ([\d.]+) \(\+ search ([\d.]+) unlocked\), links ([\d.]+), graph ([\d.]+), points follow ([\d.]+)', log)
    mapping = e.get('local_mapping', {})
    return dict(
        merges=m['merges'], loops=m['loops_closed'], combined=100 * m['ate_rmse_m'],
        online=[100 * r['ate_online_rmse_m'] for r in m['robots'].values()],
        lost=sum(r['times_lost'] for r in m['robots'].values()),
        locked=[h[0] for h in holds], longest=[h[1] for h in holds],
        beside=mapping.get('keyframes_mapped_beside_a_pause', 0), phases=phases)


def main(folder):
    arms = {'before': [], 'after': []}
    for run in sorted(glob.glob(os.path.join(folder, 'r*_*')), key=lambda p: (int(re.search(r'r(\d+)_', p).group(1)), p)):
        if not os.path.isdir(run) or not os.path.exists(f'{run}/metrics.json'):
            continue
        arm = run.rsplit('_', 1)[1]
        f = run_figures(run)
        arms[arm].append(f)
        print(f"{os.path.basename(run):10s} merges {f['merges']} loops {f['loops']} combined {f['combined']:.2f} cm  "
              f"online {' / '.join(f'{o:.2f}' for o in f['online'])}  lost {f['lost']}  "
              f"locked {' / '.join(f'{x:.0f}' for x in f['locked'])} ms, longest hold {' / '.join(f'{x:.0f}' for x in f['longest'])} ms  "
              f"KFs mapped beside a pause {f['beside']}"
              + (f"  [fusion apply / search / links / graph / follow ms: {'; '.join(' / '.join(p) for p in f['phases'])}]" if f['phases'] else ''))
    for arm, runs in arms.items():
        if not runs:
            continue
        comb = [r['combined'] for r in runs]
        worst_online = [max(r['online']) for r in runs]
        # Per run: the median correction (the before build: its metrics' median), and the maximum.
        run_median = lambda key: [statistics.median(r[key]) for r in runs if r[key]]
        longest_max = max(x for r in runs for x in r['longest'])
        locked_max = max(x for r in runs for x in r['locked'])
        print(f"{arm}: {len(runs)} runs, all maps merged in {sum(r['merges'] == len(r['online']) - 1 for r in runs)}; "
              f"combined final median {statistics.median(comb):.2f} worst {max(comb):.2f} cm; "
              f"worst robot online median {statistics.median(worst_online):.2f} worst {max(worst_online):.2f} cm; "
              f"per correction, under the lock: run medians {statistics.median(run_median('locked')):.0f} (median) max {locked_max:.0f} ms, "
              f"longest hold: run medians {statistics.median(run_median('longest')):.0f} max {longest_max:.0f} ms; "
              f"KFs mapped beside a pause {sum(r['beside'] for r in runs)}")


if __name__ == '__main__':
    main(sys.argv[1])
