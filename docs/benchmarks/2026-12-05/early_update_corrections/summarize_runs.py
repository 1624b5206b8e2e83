import json, re, sys, numpy as np
rows = []
for d in sys.argv[1:]:
    try:
        m = json.load(open(d + '/metrics.json')); e = json.load(open(d + '/edge_metrics.json'))
        log = open(d + '.log').read()
    except Exception as ex:
        print(d, 'missing', ex); continue
    on = re.search(r'as tracked ([\d.]+) cm; largest jump at an update ([\d.]+)', log)
    dur = 23.6 if 'fr1' in d else 30.0
    print('%-10s final %.2f online %5s jump %5s early %d updates %d loops %d down %.2f Mbit/s' % (
        d, m['ate_rmse_m'] * 100, on.group(1) if on else '?', on.group(2) if on else '?',
        e['updates_on_divergence'], e['updates_sent'], e['loops_closed'], e['update_bytes_sent'] * 8 / dur / 1e6))
