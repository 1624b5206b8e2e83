# Per minute of a long split run: the edge's largest RSS (proc.csv), its live heap and arena (the
# "heap" rows of edge_stats.csv) and the longest free-page release. Usage: edge_per_minute.py <run dir>
import csv, sys, numpy as np
d=sys.argv[1]
rows=[r for r in csv.DictReader(open(d+'/proc.csv')) if r['role']=='edge']
t=np.array([float(r['t']) for r in rows]); m=np.array([float(r['rss_kb']) for r in rows])/1024
t0=t[0]; t-=t0
heap=[r for r in csv.DictReader(open(d+'/edge_stats.csv')) if r['event']=='heap']
H=[(float(r['wall_time'])-t0, dict(kv.split('=',1) for kv in r['detail'].split())) for r in heap]
out=[]
for k in range(int(t.max()//60)):
    a=np.searchsorted(t,60*k); b=np.searchsorted(t,60*(k+1))-1
    hs=[h for tt,h in H if 60*k<=tt<60*(k+1)]
    iu=np.mean([float(h['in_use_kb']) for h in hs])/1024 if hs else float('nan')
    ar=max([float(h['arena_kb']) for h in hs])/1024 if hs else float('nan')
    rel=[float(h['release_ms']) for h in hs if 'release_ms' in h]
    out.append(f"{k}: rss {m[a:b+1].max():.0f} in_use {iu:.0f} arena {ar:.0f} rel_ms {max(rel) if rel else 0:.1f}")
print("\n".join(out))
