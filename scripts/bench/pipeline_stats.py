"""Map-update pipeline figures (paper Table 4) from a split run's mobile_stats.csv / edge_stats.csv.

The two CSVs hold one row per event (KeyFrame sent/received, update built/published/accepted/
rejected, Local-Map rebuilt ...). This module does not hard-code their columns: it takes the
column that names the event (event/kind/type/name), summarises every numeric column per event
(count, median, p95) and derives the intervals between successive publish / accept events,
so new columns or events show up in the report without changing it.
"""
import os

import numpy as np

from bench_data import read_csv, stats

EVENT_COLUMNS = ("event", "kind", "type", "name")
TIME_COLUMNS = ("t", "wall", "time", "stamp", "wall_time")


def _numeric(rows, col):
    out = []
    for r in rows:
        try:
            out.append(float(r[col]))
        except (TypeError, ValueError):
            pass
    return out


def summarize_csv(path):
    rows = read_csv(path)
    if not rows:
        return None
    cols = list(rows[0].keys())
    event_col = next((c for c in EVENT_COLUMNS if c in cols), None)
    time_col = next((c for c in TIME_COLUMNS if c in cols), None)
    groups = {}
    for r in rows:
        groups.setdefault(r[event_col] if event_col else "row", []).append(r)
    out = {}
    for event, mine in groups.items():
        entry = {"count": len(mine)}
        for col in cols:
            if col in (event_col, time_col):
                continue
            values = _numeric(mine, col)
            if values and len(values) == len(mine):
                entry[col] = stats(values)
        if time_col and len(mine) > 1:
            t = np.array(_numeric(mine, time_col))
            if len(t) > 1:
                entry["interval_s"] = stats(np.diff(np.sort(t)))
        out[event] = entry
    return out


def summarize(run_dir):
    result = {}
    for side in ("mobile", "edge"):
        s = summarize_csv(os.path.join(run_dir, f"{side}_stats.csv"))
        if s is not None:
            result[side] = s
    return result


def table_rows(pipe):
    """Rows [figure, split, split+controller] for every (side, event, column) found."""
    keys = []
    for variant in pipe.values():
        for side, events in variant.items():
            for event, entry in events.items():
                for col, s in entry.items():
                    if (side, event, col) not in keys:
                        keys.append((side, event, col))
    rows = []
    for side, event, col in keys:
        cells = [f"{side}: {event} {'' if col == 'count' else col}".strip()]
        for variant in ("split", "split_controller"):
            v = pipe.get(variant, {}).get(side, {}).get(event, {}).get(col)
            if v is None:
                cells.append("n/a")
            elif col == "count":
                cells.append(str(v))
            else:
                cells.append(f"median {v['median']:.3g}, p95 {v['p95']:.3g} (n={v['count']})")
        rows.append(cells)
    return rows


def rebuild_median(pipe_variant):
    """Median Local-Map rebuild latency (ms) on the mobile, if the stats have it."""
    for event, entry in (pipe_variant or {}).get("mobile", {}).items():
        for col, s in entry.items():
            if isinstance(s, dict) and "rebuild" in f"{event} {col}".lower() and "ms" in col.lower():
                return s["median"]
    return None
