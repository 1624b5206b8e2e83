"""Table of the split pairs run by run_pairs.sh: final and online ATE, KeyFrames, KB per
KeyFrame, KeyFrame upload (bytes over the sequence's duration), update download, largest jump
at an update, times lost; then median and worst per arm. Usage: analyse_pairs.py <out folder>"""
import glob
import json
import os
import statistics
import sys


def sequence_seconds(run):
    stamps = [float(line.split()[0]) for line in open(os.path.join(run, 'trajectory.txt'))
              if line.strip() and not line.startswith('#')]
    return (stamps[-1] - stamps[0]) * len(stamps) / max(1, len(stamps) - 1)


def row(run):
    m = json.load(open(os.path.join(run, 'metrics.json')))
    seconds = sequence_seconds(run)
    nan = float('nan')
    sent = m.get('keyframe_bytes_sent', nan)  # split only; a monolithic run sends nothing
    return dict(final=100 * m['ate_rmse_m'], online=100 * m.get('ate_online_rmse_m', nan), kfs=m['keyframes_created'],
                kb=sent / max(1, m.get('keyframes_sent', 1)) / 1000, up=8e-6 * sent / seconds,
                down=8e-6 * m.get('update_bytes_received', nan) / seconds,
                jump=100 * m.get('update_jump_max_m', nan), lost=m['times_lost'])


def main(out):
    keys = ['final', 'online', 'kfs', 'kb', 'up', 'down', 'jump', 'lost']
    arms = {}
    print('| pair | arm | final ATE cm | online ATE cm | KeyFrames made | KB per KeyFrame | KeyFrame upload Mbit/s '
          '| update download Mbit/s | largest jump at an update cm | lost |')
    print('|' + '---|' * 10)
    for run in sorted(glob.glob(os.path.join(out, 'r*_*')), key=lambda p: (int(os.path.basename(p)[1:].split('_')[0]), p)):
        metrics = os.path.join(run, 'metrics.json')
        if not os.path.isfile(metrics) or 'ate_rmse_m' not in json.load(open(metrics)):
            continue  # not finished
        pair, arm = os.path.basename(run)[1:].split('_')
        r = row(run)
        arms.setdefault(arm, []).append(r)
        print('| %s | %s | ' % (pair, arm) + ' | '.join(
            ('%d' % r[k]) if k in ('kfs', 'lost') else ('%.2f' % r[k] if r[k] == r[k] else '-') for k in keys) + ' |')
    for arm, rows in arms.items():
        print('%s (%d runs): ' % (arm, len(rows)) + ', '.join(
            '%s median %.2f worst %.2f' % (k, statistics.median(r[k] for r in rows),
                                           (min if k == 'none' else max)(r[k] for r in rows)) for k in keys))


if __name__ == '__main__':
    main(sys.argv[1])
