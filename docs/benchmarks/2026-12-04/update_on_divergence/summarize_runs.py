import json, glob, os, sys, statistics as st
root = sys.argv[1]
rows = {}
for d in sorted(glob.glob(f"{root}/*_*")):
    if not os.path.isdir(d): continue
    tag, i = os.path.basename(d).rsplit("_", 1)
    try: m = json.load(open(f"{d}/metrics.json"))
    except Exception as e: print(d, "no metrics", e); continue
    e = m.get("edge", {})
    dur = 24.1 if "fr1" in root else 30.0
    r = dict(final=m["ate_rmse_m"]*100, online=(m.get("ate_online_rmse_m") or float("nan"))*100,
             jump=(m.get("update_jump_max_m") or float("nan"))*100, kf=m.get("keyframes_created", m.get("keyframes_made", m.get("keyframes"))),
             early=e.get("updates_on_divergence", 0), upd=m.get("updates", {}).get("accepted") if isinstance(m.get("updates"), dict) else None,
             lost=m.get("times_lost"), loops=m.get("loops_closed"),
             up=m.get("keyframe_bytes_sent", 0)*8/dur/1e6, down=m.get("update_bytes_received", 0)*8/dur/1e6,
             ref2=m.get("keyframes_refused_condition2"))
    dv = e.get("mobile_divergence_cm")
    if isinstance(dv, dict): r["div_max"] = dv.get("max")
    rows.setdefault(tag, []).append((int(i), r))
for tag, lst in rows.items():
    lst.sort()
    print(f"== {tag} ({len(lst)} runs)")
    for i, r in lst:
        print(f"  {i}: " + " ".join(f"{k}={v:.2f}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items()))
    for k in ("final", "online", "jump", "kf", "up", "down"):
        v = [r[k] for _, r in lst if isinstance(r.get(k), (int, float))]
        if v: print(f"  {k}: median {st.median(v):.2f} worst {max(v):.2f}")
