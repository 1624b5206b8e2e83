"""The figures of a multi-robot run (`make eval MODE=multi`, scripts/eval_multi.sh) from its output
folder: per robot the online ATE (its poses as tracked, in its own map frame, its own alignment)
and the final ATE alone; the combined final ATE (every robot's final trajectory in the edge's world
frame, ONE alignment against all ground truths: bench.multi_ate); the number of map merges.

python3 -m bench.multi_eval <OUT> --robot <name> <TUM folder> <time offset s> <source> [--robot ...]
                            [--json]
(venv python: evo). Reads OUT/edge_metrics.json, OUT/<name>/{mobile_metrics.json,
trajectory_online.txt, trajectory.txt} (trajectory.txt: the final trajectory composed by
compose_trajectory from the robot's anchors and the edge's KeyFrames, world frame). A robot played
with a time offset (its stamps moved onto the clock robot's time) is compared with its ground truth
moved by the same offset, written to OUT/<name>/groundtruth.txt. Merges: the edge's metrics
("merges": the list of merges), else the "merge" events of OUT/edge_stats.csv.
Writes OUT/metrics.json and prints one summary line per figure. A figure that cannot be computed
(no final trajectory, too few poses) is null in metrics.json, with its reason under "notes".
"""
import argparse
import json
import os
import sys

from .ate import ate_stats
from .multi_ate import combined_ate
from .bench_data import read_csv, read_json as load_json

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'edge_slam_common', 'python'))
from edge_slam_common.tum import InputError, data_lines, read_poses, stamp_seconds  # noqa: E402


def write_shifted_groundtruth(src, dst, offset):
    """src's poses with every stamp moved by `offset` s (exact to the microsecond), to dst."""
    poses = read_poses(src, normalize=False)
    if not poses:
        raise InputError('%s: no poses' % src)
    offset_us = int(round(offset * 1e6))
    with open(dst + '.tmp', 'w') as f:
        f.write('# %s, stamps moved by %+.6f s (the robot was played on the clock robot\'s time)\n' % (src, offset))
        for (secs, nsecs), values, _ in poses:
            us = secs * 1000000 + nsecs // 1000 + offset_us
            f.write('%d.%06d %s\n' % (us // 1000000, us % 1000000, ' '.join(repr(v) for v in values)))
    os.replace(dst + '.tmp', dst)


def merges_count(out):
    """(number of merges, where it came from), (None, reason) when the edge wrote none. The edge's
    metrics.json lists every merge ("merges": [{keyframe, loop_keyframe, robot, loop_robot,
    matches, T_into_from}], split/edge_system.cpp); its event CSV has one "merge" row each."""
    edge = load_json(os.path.join(out, 'edge_metrics.json')) or {}
    if isinstance(edge.get('merges'), list):
        return len(edge['merges']), 'edge_metrics.json merges'
    rows = read_csv(os.path.join(out, 'edge_stats.csv')) or []
    if rows and 'event' in rows[0]:
        return sum(1 for r in rows if r.get('event') == 'merge'), 'edge_stats.csv "merge" events'
    return None, 'no merges figure: neither edge_metrics.json "merges" nor edge_stats.csv'


def summarize(out, robots):
    """robots: [(name, TUM folder, offset s, source)]. Returns (metrics dict, summary lines)."""
    m = {'mode': 'multi', 'robots': {}, 'notes': []}
    edge = load_json(os.path.join(out, 'edge_metrics.json'))
    if edge is None:
        m['notes'].append('no edge_metrics.json')
    m['edge'] = edge
    lines = []
    finals = []
    for name, folder, offset, source in robots:
        r = {'dataset': folder, 'time_offset_s': offset, 'source': source}
        d = os.path.join(out, name)
        gt_src = os.path.join(folder, 'groundtruth.txt')
        gt = os.path.join(d, 'groundtruth.txt')
        os.makedirs(d, exist_ok=True)
        write_shifted_groundtruth(gt_src, gt, offset)
        mobile = load_json(os.path.join(d, 'mobile_metrics.json'))
        if mobile is None:
            m['notes'].append('%s: no mobile_metrics.json' % name)
        else:
            for k in ('frames', 'frames_tracked', 'keyframes', 'times_lost', 'relocalizations', 'local_map_peak'):
                r[k] = mobile.get(k)
            r['updates'] = mobile.get('updates')
        for key, path in (('online', 'trajectory_online.txt'), ('final', 'trajectory.txt')):
            traj = os.path.join(d, path)
            r['ate_%s_rmse_m' % key] = None
            if not os.path.isfile(traj):
                m['notes'].append('%s: no %s' % (name, path))
                continue
            try:
                s = ate_stats(gt, traj)
                r['ate_%s_rmse_m' % key] = s['ate_rmse_m']
                r['ate_%s_pairs' % key] = s['ate_pairs']
            except Exception as e:  # too few poses, no association, unreadable file
                m['notes'].append('%s: %s ATE: %s' % (name, key, e))
        if os.path.isfile(os.path.join(d, 'trajectory.txt')):
            finals.append((name, gt, os.path.join(d, 'trajectory.txt')))
        m['robots'][name] = r
        online, final = r['ate_online_rmse_m'], r['ate_final_rmse_m']
        lines.append('multi: %s online ATE (own map frame, own alignment) %s over %s poses; tracked %s/%s frames, '
                     'KeyFrames %s, lost %s times'
                     % (name, cm(online), r.get('ate_online_pairs'), r.get('frames_tracked'), r.get('frames'),
                        r.get('keyframes'), r.get('times_lost')))
        lines.append('multi: %s final ATE alone (own alignment) %s' % (name, cm(final)))
    m['ate_rmse_m'] = None
    if len(finals) == len(robots) and finals:
        try:
            c = combined_ate(finals)
            m['ate_rmse_m'] = c['ate_rmse_m']
            m['ate_pairs'] = c['ate_pairs']
            m['ate_combined'] = c
            m['ate_tool'] = c['ate_tool']
        except Exception as e:
            m['notes'].append('combined ATE: %s' % e)
    else:
        m['notes'].append('combined ATE: a robot has no final trajectory')
    shares = ', '.join('%s %s' % (n, cm(v['ate_rmse_m'])) for n, v in m.get('ate_combined', {}).get('robots', {}).items())
    lines.append('multi: combined final ATE (all robots in the world frame, one alignment) %s over %s poses%s'
                 % (cm(m['ate_rmse_m']), m.get('ate_pairs'), ' (%s)' % shares if shares else ''))
    m['merges'], m['merges_source'] = merges_count(out)
    lines.append('multi: map merges %s (%s)' % (m['merges'], m['merges_source']))
    if edge:
        k = edge.get('keyframes', {}) if isinstance(edge.get('keyframes'), dict) else {}
        m['loops_closed'] = edge.get('loops_closed')
        lines.append('multi: edge KeyFrames inserted %s, refused by condition 1 %s / condition 2 %s; loops closed %s'
                     % (k.get('inserted'), k.get('rejected_condition1'), k.get('rejected_condition2'),
                        edge.get('loops_closed')))
    for note in m['notes']:
        lines.append('multi: note: ' + note)
    with open(os.path.join(out, 'metrics.json'), 'w') as f:
        json.dump(m, f, indent=2)
        f.write('\n')
    return m, lines


def cm(v):
    return 'n/a' if v is None else '%.2f cm' % (v * 100)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('out')
    ap.add_argument('--robot', nargs=4, action='append', required=True, metavar=('NAME', 'FOLDER', 'OFFSET', 'SOURCE'),
                    help='a robot: its name (output subfolder), TUM folder, time offset (s) and source (bag/folder)')
    ap.add_argument('--json', action='store_true', help='print metrics.json instead of the summary lines')
    a = ap.parse_args()
    try:
        if not os.path.isdir(a.out):
            raise InputError('%s: output folder not found' % a.out)
        robots = []
        for name, folder, offset, source in a.robot:
            if not os.path.isfile(os.path.join(folder, 'groundtruth.txt')):
                raise InputError('%s: no groundtruth.txt in %s' % (name, folder))
            robots.append((name, folder, float(offset), source))
        m, lines = summarize(a.out, robots)
    except (InputError, OSError, ValueError) as e:
        sys.exit('bench.multi_eval: %s' % e)
    if a.json:
        print(json.dumps(m, indent=2))
    else:
        print('\n'.join(lines))
    print('multi: -> %s' % os.path.join(a.out, 'metrics.json'), file=sys.stderr)


if __name__ == '__main__':
    main()
