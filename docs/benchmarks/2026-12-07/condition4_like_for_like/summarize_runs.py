import json, glob, os, sys, statistics as st
root = sys.argv[1] if len(sys.argv) > 1 else '/tmp/rr'
rows = {}
for d in sorted(glob.glob(root + '/*-*-*-*')):
    if not os.path.isdir(d): continue
    f = d + '/metrics.json'
    if not os.path.exists(f): continue
    m = json.load(open(f))
    tag, mode, v, i = os.path.basename(d).split('-')
    r = dict(final=m.get('ate_rmse_m', float('nan')) * 100, online=m.get('ate_online_rmse_m', float('nan')) * 100,
             kfs=m.get('keyframes_created'), loops=m.get('loops_closed', m.get('edge', {}).get('loops_closed') if isinstance(m.get('edge'), dict) else None),
             lost=m.get('times_lost'))
    if mode == 'split':
        dur = m.get('duration_s') or m.get('sequence_s')
        r['kb'] = m['keyframe_bytes_sent'] / max(1, m['keyframes_sent']) / 1000
        r['jump'] = m.get('largest_update_jump_cm', m.get('online_update_jump_cm'))
        ks = m.get('keyframe_stats', {})
        r['c4'] = (round(ks.get('mean_condition4_points', 0)), round(ks.get('mean_reference_points', 0)))
        r['bytes'] = m['keyframe_bytes_sent']
    rows.setdefault((tag, mode, v), []).append((int(i), r))
for k, lst in sorted(rows.items()):
    print(k)
    for i, r in sorted(lst):
        print('  ', i, {a: (round(b, 2) if isinstance(b, float) else b) for a, b in r.items()})
    for key in ('final', 'online', 'kfs'):
        vals = [r[key] for _, r in lst if r.get(key) is not None]
        if vals: print('   %s median %.2f worst %.2f' % (key, st.median(vals), max(vals)))
