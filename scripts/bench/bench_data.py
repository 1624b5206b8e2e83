"""Readers for what one benchmark run leaves in OUT/runs/<dataset>/<variant>/ (the bottom layer of
the bench package: imports nothing of it).

Every reader returns None (or an empty result) when its file is missing, so the report can say
"not measured" for that part instead of failing: a run that crashed still yields the rest.
"""
import csv
import json
import os

import numpy as np


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def read_csv(path):
    """List of row dicts (values as strings), or None when absent."""
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(row for row in f if not row.startswith("#")))
    except OSError:
        return None


def column(rows, name, cast=float):
    out = []
    for r in rows or []:
        try:
            out.append(cast(r[name]))
        except (KeyError, TypeError, ValueError):
            pass
    return np.array(out)


def proc_series(run_dir):
    """role -> dict(t [s since the first sample of the run], cpu_s cumulative, rss_mb)."""
    rows = read_csv(os.path.join(run_dir, "proc.csv"))
    if not rows:
        return {}
    t0 = float(rows[0]["t"])
    series = {}
    for role in sorted({r["role"] for r in rows}):
        mine = [r for r in rows if r["role"] == role]
        series[role] = {"t": column(mine, "t") - t0, "cpu_s": column(mine, "cpu_s"),
                        "rss_mb": column(mine, "rss_kb") / 1024.0}
    return series


def heap_series(run_dir, side="mobile"):
    """A node's allocator readings ("heap" rows of <side>_stats.csv, every 10 s, split/memory_row.h):
    dict(t [s since the first sample of proc.csv, the same clock as proc_series], in_use_mb,
    arena_mb, keyframes_beyond_map, points_beyond_map, release_ms: the edge's free-page release after
    each reading, None where the rows have none), or None when the run has none (a monolithic run,
    or one older than the readings)."""
    procs = read_csv(os.path.join(run_dir, "proc.csv"))
    rows = [r for r in read_csv(os.path.join(run_dir, f"{side}_stats.csv")) or [] if r.get("event") == "heap"]
    if not procs or not rows:
        return None
    fields = [dict(kv.split("=", 1) for kv in r["detail"].split()) for r in rows]
    series = {"t": column(rows, "wall_time") - float(procs[0]["t"]),
              "in_use_mb": np.array([float(f["in_use_kb"]) for f in fields]) / 1024.0,
              "arena_mb": np.array([float(f["arena_kb"]) for f in fields]) / 1024.0,
              "release_ms": (np.array([float(f["release_ms"]) for f in fields])
                             if all("release_ms" in f for f in fields) else None)}
    # KeyFrames and points alive in the process beyond what the node's map holds (the mobile's
    # Local-Map, the edge's Global-Map; None for rows older than the counts): tracking's last frame
    # and an update being built or installed hold some for a moment; a count that keeps growing is a
    # leak of map objects.
    for name in ("keyframes", "points"):
        held = next((f"{m}_{name}" for m in ("local_map", "global_map")
                     if all(f"{name}_alive" in f and f"{m}_{name}" in f for f in fields)), None)
        series[f"{name}_beyond_map"] = None if held is None else np.array(
            [float(f[f"{name}_alive"]) - float(f[held]) for f in fields])
    return series


def objects_beyond_map(heap):
    """'KeyFrames / points' alive beyond the node's map, largest reading (last reading)."""
    kfs, pts = heap.get("keyframes_beyond_map"), heap.get("points_beyond_map")
    if kfs is None or pts is None or not len(kfs):
        return "n/a"
    return f"{kfs.max():.0f} / {pts.max():.0f} ({kfs[-1]:.0f} / {pts[-1]:.0f})"


def cpu_percent(t, cpu_s, window=1.0):
    """CPU % of one process over consecutive windows (cumulative CPU-seconds differenced).
    /proc counts in 10 ms ticks, so a 50 ms sample alone would read in 20 % steps."""
    if len(t) < 2:
        return np.array([]), np.array([])
    edges = np.arange(t[0], t[-1] + 1e-9, window)
    if len(edges) < 2:
        return np.array([]), np.array([])
    cpu_at = np.interp(edges, t, cpu_s)
    return 0.5 * (edges[1:] + edges[:-1]), 100.0 * np.diff(cpu_at) / np.diff(edges)


def net_rows(run_dir):
    rows = read_csv(os.path.join(run_dir, "net.csv"))
    if rows is None:
        return None
    return {"t": column(rows, "t"), "topic": np.array([r["topic"] for r in rows]), "bytes": column(rows, "bytes")}


def stats(values):
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if not len(v):
        return None
    return {"count": int(len(v)), "mean": float(v.mean()), "median": float(np.median(v)),
            "p95": float(np.percentile(v, 95)), "max": float(v.max())}


POSES_WITHOUT_ANCHOR = 4


def split_files_complete(out, pose_stamps, global_map_ids, keyframes_file=None):
    """True once a split run's files hold what the nodelets have done: an F anchor for every pose
    the mobile published (data stamps, s; the mobile flushes its anchors every second) and, in
    edge_keyframes.txt (rewritten atomically every second; default out/edge_keyframes.txt, with
    several robots the one edge's file beside the robots' folders), exactly the Global-Map
    KeyFrame ids the edge reports (its untagged lines; 'C' lines are culled KeyFrames, io/anchors_file.h)."""
    from edge_slam_common.tum import InputError, read_records
    try:
        anchors = read_records(os.path.join(out, "mobile_anchors.txt"), {"F": 10, "K": 10})
        keyframes = read_records(keyframes_file or os.path.join(out, "edge_keyframes.txt"), {None: 9, "C": 10})
    except InputError:  # not written yet
        return False
    frames = [float(w[1]) for _, w in anchors if w[0] == "F"]
    if not pose_stamps or not frames:
        return False
    in_map = {int(w[0]) for _, w in keyframes if w[0] != "C"}
    # A pose whose reference KeyFrame had just left the Local-Map has no F line: a few of the
    # newest poses may lack one.
    must_have = sorted(pose_stamps)[max(0, len(pose_stamps) - 1 - POSES_WITHOUT_ANCHOR)]
    return max(frames) >= must_have - 1e-6 and in_map == set(global_map_ids)
