# The edge's memory in one long split run, through the bench's own readers (bench_data):
# RSS mean / median / peak, then per minute the largest RSS (proc.csv), the live heap and the
# arena (edge_stats.csv's heap rows) and the longest free-page release.
# Usage, with the project's venv: PYTHONPATH=scripts .venv/bin/python3 edge_per_minute.py <run dir>
import sys

import numpy as np

from bench.bench_data import heap_series, proc_series

run = sys.argv[1]
proc, heap = proc_series(run)["edge"], heap_series(run, "edge")
rss = proc["rss_mb"]
print(f"edge RSS mean {rss.mean():.0f} median {np.median(rss):.0f} peak {rss.max():.0f} MB")
for k in range(int(proc["t"].max() // 60)):
    in_minute = (proc["t"] >= 60 * k) & (proc["t"] < 60 * (k + 1))
    rows = (heap["t"] >= 60 * k) & (heap["t"] < 60 * (k + 1))
    release = heap["release_ms"][rows].max() if heap["release_ms"] is not None and rows.any() else 0.0
    print(f"{k}: rss {rss[in_minute].max():.0f} in_use {heap['in_use_mb'][rows].mean():.0f} "
          f"arena {heap['arena_mb'][rows].max():.0f} rel_ms {release:.1f}")
