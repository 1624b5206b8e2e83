"""Map-update pipeline figures (paper Table 4) from a split run's mobile_stats.csv / edge_stats.csv.

Both CSVs hold one row per event with the schema of edge_slam_common/include/edge_slam/io/event_log.h,
read here by column name (-1 or empty = not applicable). Events used here:
  mobile  frame (duration = tracking ms, state = tracking state), keyframe_sent, frame_sent,
          update: one row when an update arrives (bytes = its wire size, latency = edge publish ->
          received, duration = Local-Map rebuild when installed, kind, decision, deferred 0), and
          for an update deferred by eq. (1) a second row with the same seq when it is finally
          applied or refused (deferred 1, bytes 0); frame_stamp = the last frame tracked before it
  edge    keyframe (latency = mobile creation -> received, decision = verdict), frame,
          update_sent (duration = construction, from build start to publish; kind: periodic,
          divergence (sent early, edge_slam/update_on_divergence) or relocalization; keyframes, points)
"""
import os

import numpy as np

from .bench_data import column, read_csv, stats


def _rows(run_dir, side):
    return read_csv(os.path.join(run_dir, f"{side}_stats.csv")) or []


def _values(rows, col, keep_negative=False):
    out = []
    for r in rows:
        try:
            v = float(r[col])
        except (KeyError, TypeError, ValueError):
            continue
        if keep_negative or v >= 0:
            out.append(v)
    return np.array(out)


def summarize(run_dir):
    """Dict of Table-4 figures (each a stats dict or a count); empty when no CSV exists."""
    mobile, edge = _rows(run_dir, "mobile"), _rows(run_dir, "edge")
    if not mobile and not edge:
        return {}
    ev = lambda rows, name: [r for r in rows if r.get("event") == name]  # noqa: E731
    updates = ev(mobile, "update")
    arrived = update_arrivals(updates)
    accepted = [r for r in updates if _values([r], "duration_ms").size]
    # The rebuild target is about the periodic 6-KeyFrame update; relocalization ones are larger.
    periodic = [r for r in accepted if update_kind(r) == "periodic"]
    decisions = {}
    for r in final_update_rows(updates):
        key = f"{update_kind(r)} {update_decision(r)}"
        decisions[key] = decisions.get(key, 0) + 1
    sent = ev(edge, "update_sent")
    # Intervals and construction are the Local-Map updates'; relocalization answers come on demand.
    # The edge labels the Local-Map updates its divergence trigger sent early "divergence"; they
    # are the same kind of update as the timer's (and the mobile sees both as periodic).
    sent_local_map = [r for r in sent if update_kind(r) in ("periodic", "divergence")]
    kf_edge = ev(edge, "keyframe")
    verdicts = {}
    for r in kf_edge:
        verdicts[r.get("decision") or "?"] = verdicts.get(r.get("decision") or "?", 0) + 1
    return {
        "keyframe_transmit_ms": stats(_values(kf_edge, "latency_ms")),
        "update_construction_ms": stats(_values(sent_local_map, "duration_ms")),
        "update_publish_interval_s": stats(np.diff(np.sort(_values(sent_local_map, "wall_time")))),
        "relocalization_update_construction_ms": stats(_values([r for r in sent if r not in sent_local_map],
                                                               "duration_ms")),
        "update_delivery_ms": stats(_values(arrived, "latency_ms")),
        "update_acceptance_interval_s": stats(np.diff(np.sort(_values(periodic, "wall_time")))),
        "local_map_rebuild_ms": stats(_values(periodic, "duration_ms")),
        "update_bytes": stats(_values(sent_local_map, "bytes")),
        "relocalization_update_bytes": stats(_values([r for r in sent if r not in sent_local_map], "bytes")),
        "keyframe_bytes": stats(_values(ev(mobile, "keyframe_sent"), "bytes")),
        "frame_bytes": stats(_values(ev(mobile, "frame_sent"), "bytes")),
        "keyframes_sent": len(ev(mobile, "keyframe_sent")),
        "keyframes_received_by_edge": len(kf_edge),
        "edge_keyframe_verdicts": verdicts,
        "updates_sent": len(sent),
        "updates_sent_on_divergence": len([r for r in sent if update_kind(r) == "divergence"]),
        "updates_received": len(arrived),
        "updates_accepted": len(accepted),
        "updates_deferred": len(updates) - len(arrived),
        "update_decisions": decisions,
        "frames_processed": len(ev(mobile, "frame")),
        "frames_tracked": sum(1 for r in ev(mobile, "frame") if r.get("state") == "OK"),
        "frames_lost": sum(1 for r in ev(mobile, "frame") if r.get("state") == "LOST"),
        "local_map_keyframes_max": int(_values(ev(mobile, "frame"), "map_keyframes").max())
        if _values(ev(mobile, "frame"), "map_keyframes").size else None,
    }


# ---- the "update" rows, read by column: kind, decision, deferred, frame_stamp.

def update_arrivals(updates):
    """One row per update message received: the second row of a deferred update (deferred = 1)
    is its outcome, not another update."""
    return [r for r in updates if r.get("deferred") != "1"]


def final_update_rows(updates):
    """The last row of each update (by seq): its final decision (a deferral's outcome)."""
    last = {}
    for r in updates:
        last[r.get("seq")] = r
    return list(last.values())


def update_kind(row):
    return row.get("kind") or "?"


def update_decision(row):
    return row.get("decision") or "?"


def applied_update_stamps(csv_path):
    """Data stamps (s) at which the mobile installed an update (rows with a rebuild duration),
    from a mobile_stats.csv path: where the online trajectory may jump. The stamp is that of the
    last frame tracked before the install (frame_stamp): the jump lies between it and the next."""
    rows = [r for r in read_csv(csv_path) or [] if r.get("event") == "update"]
    stamps = []
    for r in rows:
        if not _values([r], "duration_ms").size:
            continue
        frame = _values([r], "frame_stamp")
        stamps.append(float(frame[0]) if frame.size else float(r["data_time"]))
    return stamps


def _frame_rows(run_dir):
    """The mobile's "frame" rows of a split run's mobile_stats.csv."""
    return [r for r in _rows(run_dir, "mobile") if r.get("event") == "frame"]


def tracking_series(run_dir):
    """(data stamps, tracking ms) of every frame the mobile tracked in a split run."""
    frames = _frame_rows(run_dir)
    t, ms = _values(frames, "data_time", True), _values(frames, "duration_ms", True)
    return (t, ms) if len(t) and len(t) == len(ms) else (None, None)


def tracking_cpu_ms(run_dir):
    """CPU time of the mobile's tracking thread per frame in a split run (the cpu_ms column; None
    for a run written before it): the wall time minus waiting for a core."""
    frames = _frame_rows(run_dir)
    ms = _values(frames, "cpu_ms", True)
    return ms if len(ms) and len(ms) == len(frames) else None


def frame_times(run_dir):
    """Per-frame tracking latency (stamps, ms): frame_times.csv of the monolithic runner, or the
    mobile's "frame" events in a split run's mobile_stats.csv."""
    rows = read_csv(os.path.join(run_dir, "frame_times.csv"))
    if rows:
        return column(rows, "stamp"), column(rows, "tracking_ms")
    return tracking_series(run_dir)


TABLE = [("KeyFrame transmit latency (mobile creation -> edge received)", "keyframe_transmit_ms", "ms"),
         ("periodic update construction on the edge", "update_construction_ms", "ms"),
         ("periodic update publish interval", "update_publish_interval_s", "s"),
         ("update delivery, all kinds (edge publish -> mobile received)", "update_delivery_ms", "ms"),
         ("periodic update acceptance interval", "update_acceptance_interval_s", "s"),
         ("Local-Map rebuild on the mobile, periodic updates (tracking paused)", "local_map_rebuild_ms", "ms"),
         ("periodic update size", "update_bytes", "KB"),
         ("relocalization update construction", "relocalization_update_construction_ms", "ms"),
         ("relocalization update size", "relocalization_update_bytes", "KB"),
         ("KeyFrame size", "keyframe_bytes", "KB")]


def table_rows(pipe):
    """Rows [figure, split, split + controller]."""
    if not any(pipe.values()):
        return []

    def cell(s, unit):
        if not s:
            return "n/a"
        k = 1e-3 if unit == "KB" else 1.0
        return f"median {s['median'] * k:.3g} {unit}, p95 {s['p95'] * k:.3g} (n={s['count']})"

    rows = [[label] + [cell(pipe.get(v, {}).get(key), unit) for v in ("split", "split_controller")]
            for label, key, unit in TABLE]
    for label, key in [("mobile frames processed / tracked / lost", ("frames_processed", "frames_tracked", "frames_lost")),
                       ("KeyFrames sent / received by the edge", ("keyframes_sent", "keyframes_received_by_edge")),
                       ("updates sent / received / accepted", ("updates_sent", "updates_received", "updates_accepted"))]:
        rows.append([label] + [" / ".join(str(pipe.get(v, {}).get(k, "n/a")) for k in key)
                               for v in ("split", "split_controller")])
    for label, key in [("update decisions on the mobile", "update_decisions"),
                       ("edge verdicts on KeyFrames", "edge_keyframe_verdicts")]:
        rows.append([label] + [", ".join(f"{k}: {n}" for k, n in sorted((pipe.get(v, {}).get(key) or {}).items()))
                               or "n/a" for v in ("split", "split_controller")])
    return rows


def rebuild_median(pipe_variant):
    s = (pipe_variant or {}).get("local_map_rebuild_ms")
    return s["median"] if s else None
