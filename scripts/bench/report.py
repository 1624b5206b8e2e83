#!/usr/bin/env python3
"""Benchmark report: OUT/runs/ (written by bench.py) -> OUT/report.md, OUT/bench.json, OUT/*.png.

report.py --out <dir>        (venv python: evo for the ATE, matplotlib for the plots)

Sections follow the paper's evaluation (section 5) and issue "Benchmark suite"; every target
of the issue gets PASS / MISS / not measured next to its figure. Missing inputs (a crashed run,
split mode not available, no stats CSV) give "not measured" lines, never a crash.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_data import (cpu_percent, frame_times, net_rows, proc_series, read_json, stats)  # noqa: E402
import pipeline_stats  # noqa: E402
import speed  # noqa: E402

MODES = ["monolithic", "split"]
COLORS = {"groundtruth": "0.55", "monolithic": "tab:blue", "split": "tab:orange", "edge": "tab:green",
          "split_controller": "tab:red"}
UPLOAD_TOPICS, DOWNLOAD_TOPICS = ("keyframes", "frames"), ("map_updates",)


def verdict(ok):
    return "not measured" if ok is None else ("**PASS**" if ok else "**MISS**")


def fmt(v, spec=".2f", unit=""):
    return "n/a" if v is None else f"{v:{spec}}{unit}"


# ---------------------------------------------------------------- accuracy (Table 2, Fig. 6)

def ate(groundtruth, trajectory):
    """evo APE (translation, SE(3) Umeyama alignment, no scale) = `evo_ape tum gt traj -a`."""
    from evo.core import metrics, sync
    from evo.tools import file_interface
    if not os.path.isfile(trajectory):
        return None
    try:
        ref = file_interface.read_tum_trajectory_file(groundtruth)
        est = file_interface.read_tum_trajectory_file(trajectory)
        ref, est = sync.associate_trajectories(ref, est, max_diff=0.01)
        est.align(ref, correct_scale=False)
        ape = metrics.APE(metrics.PoseRelation.translation_part)
        ape.process_data((ref, est))
    except Exception as e:  # evo raises its own types for empty/unsynchronisable files
        print(f"report: ATE of {trajectory}: {e}", file=sys.stderr)
        return None
    s = ape.get_all_statistics()
    return {"rmse_m": s["rmse"], "mean_m": s["mean"], "std_m": s["std"], "max_m": s["max"],
            "poses": int(est.num_poses), "ref_xyz": ref.positions_xyz, "est_xyz": est.positions_xyz}


def plot_trajectories(path, name, results):
    """Top view on the ground truth's two widest axes, estimates aligned to it."""
    first = next((r for r in results.values() if r), None)
    if first is None:
        return False
    ref = first["ref_xyz"]
    axes = np.argsort(-np.ptp(ref, axis=0))[:2]
    labels = "xyz"
    fig, ax = plt.subplots(figsize=(7, 5.5))
    ax.plot(ref[:, axes[0]], ref[:, axes[1]], color=COLORS["groundtruth"], lw=3.5, alpha=0.6, label="ground truth")
    for mode, r in results.items():
        if r:
            est = r["est_xyz"]
            ax.plot(est[:, axes[0]], est[:, axes[1]], color=COLORS[mode], lw=1.2,
                    label=f"{mode} (ATE {r['rmse_m'] * 100:.2f} cm)")
    ax.set_xlabel(f"{labels[axes[0]]} [m]")
    ax.set_ylabel(f"{labels[axes[1]]} [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    ax.set_title(f"{name}: trajectories over ground truth (SE(3)-aligned)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


# ---------------------------------------------------------------- latency (Fig. 7)

def plot_tracking(path, name, series, t0, turn):
    """series: mode -> (stamps, ms); t0: the sequence's first stamp; turn: fastest-turn window."""
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.axvspan(turn[0] - t0, turn[1] - t0, color="0.85", label="fastest turn (ground truth)")
    drawn = False
    for mode, (t, ms) in series.items():
        if t is None or not len(t):
            continue
        t = t - t0
        ax.plot(t, ms, color=COLORS[mode], lw=0.6, alpha=0.3)
        k = 15  # half a second at 30 fps
        if len(ms) > k:
            ax.plot(t[k - 1:], np.convolve(ms, np.ones(k) / k, mode="valid"), color=COLORS[mode], lw=1.8,
                    label=f"{mode} (0.5 s mean; median {np.median(ms):.1f} ms)")
        drawn = True
    if not drawn:
        plt.close(fig)
        return False
    ax.set_xlabel("sequence time [s]")
    ax.set_ylabel("tracking latency per frame [ms]")
    ax.set_ylim(0, max(10.0, np.percentile(np.concatenate([s[1] for s in series.values() if s[0] is not None]),
                                           99.5) * 1.15))
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=9)
    ax.set_title(f"{name}: mobile tracking latency over time (faint: every frame)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


# ---------------------------------------------------------------- CPU and memory (Fig. 8)

def plot_cpu_memory(path, name, procs):
    """procs: label -> proc series dict (t, cpu_s, rss_mb)."""
    if not procs:
        return False
    fig, (a_cpu, a_rss) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    for label, p in procs.items():
        color = COLORS["edge"] if label.startswith("edge") else COLORS[label.split()[-1]]
        style = "--" if label.startswith("edge") else "-"
        tc, pct = cpu_percent(p["t"], p["cpu_s"])
        a_cpu.plot(tc, pct, style, color=color, lw=1.4, label=f"{label} ({p['cpu_s'][-1]:.1f} CPU-s)")
        a_rss.plot(p["t"], p["rss_mb"], style, color=color, lw=1.4, label=f"{label} (peak {p['rss_mb'].max():.0f} MB)")
    a_cpu.set_ylabel("CPU [% of one core, 1 s windows]")
    a_rss.set_ylabel("resident memory (VmRSS) [MB]")
    a_rss.set_xlabel("time since the process started [s]")
    for a in (a_cpu, a_rss):
        a.grid(alpha=0.3)
        a.legend(loc="best", fontsize=8)
        a.set_ylim(bottom=0)
    a_cpu.set_title(f"{name}: CPU and memory of the mobile (and edge) process, /proc at 20 Hz")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


# ---------------------------------------------------------------- network (Fig. 9)

def network_summary(net, seconds):
    if net is None or not len(net["t"]):
        return None
    out = {"per_topic": {}}
    for topic in sorted(set(net["topic"])):
        b = net["bytes"][net["topic"] == topic]
        out["per_topic"][topic] = {"messages": int(len(b)), "bytes_total": int(b.sum()),
                                   "bytes_mean": float(b.mean()), "bytes_median": float(np.median(b)),
                                   "bytes_max": int(b.max())}
    up = sum(v["bytes_total"] for k, v in out["per_topic"].items() if k in UPLOAD_TOPICS)
    down = sum(v["bytes_total"] for k, v in out["per_topic"].items() if k in DOWNLOAD_TOPICS)
    out["seconds"] = seconds
    out["upload_mbps"] = up * 8 / seconds / 1e6
    out["download_mbps"] = down * 8 / seconds / 1e6
    return out


def plot_network(path, name, net):
    if net is None or not len(net["t"]):
        return False
    t0 = net["t"].min()
    fig, ax = plt.subplots(figsize=(9, 4))
    edges = np.arange(0, net["t"].max() - t0 + 1.0, 1.0)
    for topic, color in (("keyframes", "tab:blue"), ("frames", "tab:purple"), ("map_updates", "tab:orange")):
        sel = net["topic"] == topic
        if not sel.any():
            continue
        mbits, _ = np.histogram(net["t"][sel] - t0, bins=edges, weights=net["bytes"][sel] * 8 / 1e6)
        direction = "upload" if topic in UPLOAD_TOPICS else "download"
        ax.step(edges[:-1], mbits, where="post", color=color, lw=1.3,
                label=f"{topic} ({direction}, {net['bytes'][sel].sum() / 1e6:.2f} MB in {sel.sum()} msgs)")
    ax.set_xlabel("time since the first message [s]")
    ax.set_ylabel("bandwidth [Mbit/s, 1 s bins]")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"{name}: split-mode traffic per topic (serialized message bytes)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


# ---------------------------------------------------------------- relocalization (Table 3)

def relocalization(run_dir, blank_range):
    """Relocalization count (runner metrics) and latency: the gap from the last blank frame to
    the first tracked pose after it, read off the trajectory (works for both modes)."""
    m = read_json(os.path.join(run_dir, "metrics.json"))
    traj = os.path.join(run_dir, "trajectory.txt")
    if m is None or blank_range is None:
        return None
    out = {"relocalizations": m.get("relocalizations"), "times_lost": m.get("times_lost"),
           "frames_tracked": m.get("frames_tracked"), "frames": m.get("frames")}
    if os.path.isfile(traj):
        stamps = np.array([float(l.split()[0]) for l in open(traj) if l.strip() and l[0] != "#"])
        after = stamps[stamps > blank_range[1]]
        out["first_pose_after_blank_s"] = float(after[0] - blank_range[1]) if len(after) else None
    return out


# ---------------------------------------------------------------- long run (RSS slope)

WARM_UP_S = 120.0


def rss_slope(p, seconds):
    """MB/min of a least-squares line through the RSS samples from WARM_UP_S after the process
    started to the end of the camera data (the final global BA after it is not steady state)."""
    sel = (p["t"] >= WARM_UP_S) & (p["t"] <= seconds)
    if sel.sum() < 20:
        return None
    return float(np.polyfit(p["t"][sel] / 60.0, p["rss_mb"][sel], 1)[0])


def long_run(manifest, out, rep, section, bench):
    entry = manifest.get("long_run")
    section.line("## Long run: mobile memory over 10+ minutes")
    section.line()
    if not entry:
        why = manifest.get("long_run_skipped", "not run")
        section.line(f"not measured ({why}).")
        section.line()
        rep.target("Mobile RSS slope after warm-up <= 0.5 MB/min (split, long run)", f"not measured: {why}", None)
        return
    procs, rows, slopes = {}, [], {}
    for mode in MODES:
        series = proc_series(os.path.join(out, "runs", entry["name"], f"long_{mode}"))
        for role, p in series.items():
            label = f"{role} {mode}" if role == "mobile" else f"edge ({mode})"
            procs[label] = p
            slope = rss_slope(p, entry["seconds"])
            slopes[label] = slope
            rows.append([label, fmt(p["cpu_s"][-1], ".1f"), fmt(p["rss_mb"].max(), ".0f"), fmt(slope, ".2f", " MB/min")])
    bench["long_run"] = {"seconds": entry["seconds"], "rss_slope_mb_per_min": slopes, "warm_up_s": WARM_UP_S}
    section.line(f"`{entry['name']}`: {entry['seconds'] / 60:.1f} min of camera data (the embedded sequence's closed "
                 f"path driven {entry.get('laps', 20)} times at 15 fps, scripts/bench/loop_sequence.py; the split plays it live from the "
                 "folder with tum_player). RSS slope = least-squares "
                 f"line through the samples from {WARM_UP_S:.0f} s after start to the end of the camera data.")
    section.line()
    section.table(["process", "CPU-seconds", "peak RSS [MB]", "RSS slope after warm-up"], rows)
    ran = {r["variant"] for r in entry.get("runs", [])}
    if "long_split" not in ran:
        section.line("Split mode on the long sequence: **not measured** (`make bench BENCH_ARGS=\"--add --only long "
                     "--long-modes split\"` adds it).")
        section.line()
    slope = slopes.get("mobile split")
    rep.target("Mobile RSS slope after warm-up <= 0.5 MB/min (split, long run)",
               "not measured: no split long run" if slope is None else f"{slope:.2f} MB/min (monolithic: "
               f"{fmt(slopes.get('mobile monolithic'), '.2f')} MB/min)", None if slope is None else slope <= 0.5)
    if plot_cpu_memory(os.path.join(out, "cpu_memory_long.png"), entry["name"], procs):
        section.image("cpu_memory_long.png", "long run CPU and memory")


# ---------------------------------------------------------------- the report

class Report:
    def __init__(self, out_dir):
        self.out, self.md, self.data, self.targets = out_dir, [], {}, []

    def line(self, text=""):
        self.md.append(text)

    def table(self, header, rows):
        self.line("| " + " | ".join(header) + " |")
        self.line("|" + "---|" * len(header))
        for r in rows:
            self.line("| " + " | ".join(str(c) for c in r) + " |")
        self.line()

    def image(self, filename, alt):
        self.line(f"![{alt}]({filename})")
        self.line()

    def target(self, name, figure, ok):
        self.targets.append((name, figure, verdict(ok)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    manifest = read_json(os.path.join(out, "manifest.json")) or {"datasets": [], "machine": {}}
    rep = Report(out)
    wire = read_json(os.path.join(out, "wire.json"))
    bench = {"machine": manifest.get("machine"), "bench_wall_s": manifest.get("bench_wall_s"), "datasets": {},
             "wire": wire}
    body = Report(out)  # sections; the targets summary goes on top

    for ds in manifest["datasets"]:
        name, gt = ds["name"], os.path.join(ds["path"], "groundtruth.txt")
        run = lambda v: os.path.join(out, "runs", name, v)  # noqa: E731
        ran = {r["variant"]: r for r in ds["runs"]}
        d = bench["datasets"].setdefault(name, {"seconds": ds["seconds"], "runs": ran})
        body.line(f"## {name}")
        body.line()
        body.line(f"{ds['seconds']:.1f} s of camera data, played in real time. Runs: " + ", ".join(
            f"{v} ({'ok' if r['exit_code'] == 0 else 'FAILED, exit %d' % r['exit_code']}, {r['wall_s']:.0f} s)"
            for v, r in ran.items()) + ".")
        body.line()

        # 1. Accuracy
        body.line("### 1. Accuracy (paper Table 2, Fig. 6)")
        body.line()
        acc, rows = {}, []
        for mode in MODES:
            m = read_json(os.path.join(run(mode), "metrics.json")) or {}
            a = ate(gt, os.path.join(run(mode), "trajectory.txt")) if mode in ran else None
            acc[mode] = a
            d.setdefault("accuracy", {})[mode] = None if a is None else {
                k: v for k, v in a.items() if not k.endswith("_xyz")} | {
                "frames": m.get("frames"), "frames_tracked": m.get("frames_tracked"),
                "keyframes": m.get("keyframes"), "loops_closed": m.get("loops_closed")}
            rows.append([mode, f"{m.get('frames_tracked', 'n/a')}/{m.get('frames', 'n/a')}", m.get("keyframes", "n/a"),
                         m.get("loops_closed", "n/a")] +
                        ([fmt(a["rmse_m"] * 100), fmt(a["mean_m"] * 100), fmt(a["std_m"] * 100), a["poses"]]
                         if a else ["not measured"] * 4))
        body.table(["mode", "frames tracked / received", "keyframes", "loops", "ATE RMSE [cm]", "mean [cm]",
                    "std [cm]", "poses"], rows)
        body.line("Frames received: the monolithic runner reads every associated colour/depth pair; the split "
                  "mobile takes what rosbag plays in real time and drops frames it cannot keep up with "
                  "(subscriber queues of 2), so on a loaded machine it sees fewer. Split ATE is of its final "
                  "trajectory (frames re-anchored on the edge's final KeyFrames, `make eval MODE=split`).")
        body.line()
        ok = None
        if acc["monolithic"] and acc["split"]:
            ratio = acc["split"]["rmse_m"] / acc["monolithic"]["rmse_m"]
            ok = ratio <= 1.1
            figure = f"split {acc['split']['rmse_m'] * 100:.2f} cm / monolithic {acc['monolithic']['rmse_m'] * 100:.2f} cm = {ratio:.2f}x"
            d["accuracy"]["split_over_monolithic"] = ratio
        else:
            figure = "split run " + ("missing" if not acc["split"] else "ok") + ", monolithic " + \
                     ("missing" if not acc["monolithic"] else "ok")
        body.line(f"Target split ATE <= 1.1x monolithic: {figure} -> {verdict(ok)}")
        body.line()
        rep.target(f"Split ATE <= 1.1x monolithic ({name})", figure, ok)
        if plot_trajectories(os.path.join(out, f"trajectory_{name}.png"), name, acc):
            body.image(f"trajectory_{name}.png", f"{name} trajectories")

        # 2. Module latency
        body.line("### 2. Module latency (paper Fig. 7)")
        body.line()
        rows = []
        modules = [("tracking", "tracking_ms"), ("local mapping (per KeyFrame)", "local_mapping_ms"),
                   ("local BA", "local_ba_ms"), ("loop detection", "loop_detection_ms"),
                   ("loop correction", "loop_correction_ms"), ("full BA", "full_ba_ms")]
        for mode in MODES:
            m = read_json(os.path.join(run(mode), "metrics.json")) or {}
            for label, key in modules:
                s = m.get(key)
                d.setdefault("latency_ms", {}).setdefault(mode, {})[key] = s
                if s and s.get("count"):
                    rows.append([mode, label, s.get("count", "n/a"), fmt(s.get("mean")), fmt(s.get("median")),
                                 fmt(s.get("p95")), fmt(s.get("max"))])
        if rows:
            body.table(["mode", "module", "count", "mean [ms]", "median [ms]", "p95 [ms]", "max [ms]"], rows)
        else:
            body.line("not measured (no metrics.json)")
            body.line()
        series = {mode: frame_times(run(mode)) for mode in MODES}
        t0 = ds["fast_turn"][0] - ds.get("fast_turn_from_start", [0])[0]
        if plot_tracking(os.path.join(out, f"tracking_{name}.png"), name, series, t0, ds["fast_turn"]):
            body.image(f"tracking_{name}.png", f"{name} tracking latency")
        missing = [m for m, s in series.items() if s[0] is None]
        if missing:
            body.line(f"Per-frame tracking latency not available for: {', '.join(missing)} "
                      "(needs frame_times.csv or per-frame rows in mobile_stats.csv).")
            body.line()

        # 3. CPU and memory
        body.line("### 3. Mobile CPU and memory (paper Fig. 8)")
        body.line()
        procs, rows = {}, []
        for mode in MODES:
            for role, p in proc_series(run(mode)).items():
                label = f"{role} {mode}" if role == "mobile" else f"edge ({mode})"
                procs[label] = p
                tc, pct = cpu_percent(p["t"], p["cpu_s"])
                d.setdefault("cpu_memory", {})[label] = {
                    "cpu_seconds": float(p["cpu_s"][-1]), "mean_cpu_percent": float(pct.mean()) if len(pct) else None,
                    "peak_cpu_percent": float(pct.max()) if len(pct) else None,
                    "peak_rss_mb": float(p["rss_mb"].max()), "final_rss_mb": float(p["rss_mb"][-1]),
                    "samples": int(len(p["t"])), "sample_hz": float((len(p["t"]) - 1) / max(p["t"][-1], 1e-9))}
                c = d["cpu_memory"][label]
                rows.append([label, fmt(c["cpu_seconds"], ".1f"), fmt(c["mean_cpu_percent"], ".0f"),
                             fmt(c["peak_cpu_percent"], ".0f"), fmt(c["peak_rss_mb"], ".0f"),
                             fmt(c["final_rss_mb"], ".0f"), f"{c['samples']} @ {c['sample_hz']:.1f} Hz"])
        if rows:
            body.line("CPU-seconds = utime + stime of the whole process life, from /proc: vocabulary loading, "
                      "tracking and, in monolithic mode, Local-Mapping catching up and the final global BA "
                      "after the camera data ended.")
            body.line()
            body.table(["process", "CPU-seconds", "mean CPU %", "peak CPU % (1 s)", "peak RSS [MB]",
                        "final RSS [MB]", "samples"], rows)
        mono, split = procs.get("mobile monolithic"), procs.get("mobile split")
        ok = None
        if mono is not None and split is not None:
            ratio = split["cpu_s"][-1] / mono["cpu_s"][-1]
            ok = ratio <= 0.5
            figure = f"split mobile {split['cpu_s'][-1]:.1f} CPU-s / monolithic {mono['cpu_s'][-1]:.1f} CPU-s = {ratio:.2f}x"
            d["cpu_memory"]["mobile_cpu_ratio"] = ratio
        else:
            figure = "needs both a monolithic and a split run with samples"
        body.line(f"Target mobile CPU-seconds (split) <= 0.5x monolithic: {figure} -> {verdict(ok)}")
        body.line()
        rep.target(f"Mobile CPU-seconds split <= 0.5x monolithic ({name})", figure, ok)
        if plot_cpu_memory(os.path.join(out, f"cpu_memory_{name}.png"), name, procs):
            body.image(f"cpu_memory_{name}.png", f"{name} CPU and memory")

        # 4. Map-update pipeline
        body.line("### 4. Map-update pipeline (paper Table 4)")
        body.line()
        pipe = {v: pipeline_stats.summarize(run(v)) for v in ("split", "split_controller") if v in ran}
        d["map_update_pipeline"] = pipe
        ctrl = ran.get("split_controller", {}).get("controller_window")
        rows = pipeline_stats.table_rows(pipe)
        if rows:
            turn = ds.get("fast_turn_from_start", [0, 0])
            body.line("The controller run (`planner_example`) disables updates from 1.0 s before to 0.5 s after "
                      f"the fastest turn in the ground truth (t = {turn[0]:.2f}-{turn[1]:.2f} s from the start, "
                      f"peak {ds['fast_turn_peak_deg_s']:.0f} deg/s)" + ("" if ctrl else " - it did not run") + ".")
            body.line()
            body.table(["figure", "split", "split + controller"], rows)
        else:
            body.line("not measured: the split runs left no mobile_stats.csv / edge_stats.csv.")
            body.line()
        rebuild = pipeline_stats.rebuild_median(pipe.get("split"))
        source = "split run (mobile_stats.csv)"
        if rebuild is None and wire and wire.get("update_rebuild_ms", {}).get("count"):
            rebuild, source = wire["update_rebuild_ms"]["median"], "wire micro-benchmark (install_update)"
        if name == manifest["datasets"][0]["name"]:
            ok = None if rebuild is None else rebuild <= 20.0
            figure = "n/a" if rebuild is None else f"median {rebuild:.1f} ms ({source})"
            body.line(f"Target Local-Map rebuild from a 6-KeyFrame update, median <= 20 ms: {figure} -> {verdict(ok)}")
            body.line()
            rep.target("Local-Map rebuild (6-KeyFrame update) median <= 20 ms", figure, ok)

        # 5. Network
        body.line("### 5. Network (paper Fig. 9)")
        body.line()
        net = net_rows(run("split"))
        summary = network_summary(net, ds["seconds"])
        d["network"] = summary
        if summary:
            rows = [[t, v["messages"], fmt(v["bytes_mean"] / 1e3, ".1f"), fmt(v["bytes_median"] / 1e3, ".1f"),
                     fmt(v["bytes_max"] / 1e3, ".1f"), fmt(v["bytes_total"] / 1e6, ".2f")]
                    for t, v in summary["per_topic"].items()]
            body.table(["topic", "messages", "mean [KB]", "median [KB]", "max [KB]", "total [MB]"], rows)
            up_ok, down_ok = summary["upload_mbps"] <= 2.0, summary["download_mbps"] <= 5.0
            body.line(f"Mean over the {ds['seconds']:.1f} s sequence: upload {summary['upload_mbps']:.3f} Mbps "
                      f"(target <= 2: {verdict(up_ok)}), download {summary['download_mbps']:.3f} Mbps "
                      f"(target <= 5: {verdict(down_ok)}). 1 KB = 1000 bytes.")
            body.line()
            rep.target(f"Mean upload <= 2 Mbps ({name})", f"{summary['upload_mbps']:.3f} Mbps", up_ok)
            rep.target(f"Mean download <= 5 Mbps ({name})", f"{summary['download_mbps']:.3f} Mbps", down_ok)
        else:
            body.line("not measured: no topic recording from a split run.")
            body.line()
            rep.target(f"Mean upload <= 2 Mbps / download <= 5 Mbps ({name})", "no split run", None)
        if plot_network(os.path.join(out, f"network_{name}.png"), name, net):
            body.image(f"network_{name}.png", f"{name} network")

        # 7. Relocalization
        body.line("### 6. Relocalization with blanked frames (paper Table 3)")
        body.line()
        blank = ds.get("blank", "")
        parts = blank.split()
        blank_range = None
        if len(parts) >= 4 and parts[1] == "blank":
            lo, hi = parts[3].split("-")
            blank_range = (float(lo), float(hi))
        rows = []
        for mode in MODES:
            r = relocalization(run(f"{mode}_blank"), blank_range) if f"{mode}_blank" in ran else None
            d.setdefault("relocalization", {})[mode] = r
            if r:
                a = ate(gt, os.path.join(run(f"{mode}_blank"), "trajectory.txt"))
                r["ate_rmse_m"] = a["rmse_m"] if a else None
                rows.append([mode, r["times_lost"], r["relocalizations"], fmt(r.get("first_pose_after_blank_s"), ".2f", " s"),
                             f"{r['frames_tracked']}/{r['frames']}", fmt(a["rmse_m"] * 100 if a else None)])
            else:
                rows.append([mode] + ["not measured"] * 5)
        body.line(f"Copy with {blank} (black colour images, depth kept)." if blank else "Not run.")
        body.line()
        body.table(["mode", "times lost", "relocalizations", "first pose after the blank run", "frames tracked",
                    "ATE RMSE [cm]"], rows)

        # 6. Bandwidth limits
        body.line("### 7. Bandwidth limits (paper Table 5)")
        body.line()
        if ds.get("bandwidth"):
            rows, d["bandwidth"] = [], []
            for level in ds["bandwidth"]:
                bdir = run(f"bandwidth_{level['level']}")
                c = read_json(os.path.join(bdir, "counters.json")) or {}
                a = ate(gt, os.path.join(bdir, "trajectory.txt"))
                mob, edge = c.get("mobile") or {}, c.get("edge") or {}
                num = lambda dct, k: int(dct[k]) if str(dct.get(k, "")).isdigit() else None  # noqa: E731
                created, received, inserted = num(mob, "keyframes_created"), num(edge, "received"), num(edge, "inserted")
                dropped = created - received if created is not None and received is not None else None
                not_inserted = created - inserted if created is not None and inserted is not None else None
                d["bandwidth"].append({**level, "delay_applied": c.get("delay_applied"), "ate_rmse_m": a and a["rmse_m"],
                                       "poses": a and a["poses"], "keyframes_created": created,
                                       "keyframes_received": received, "keyframes_inserted": inserted,
                                       "keyframes_dropped_in_transit": dropped, "keyframes_not_inserted": not_inserted,
                                       "updates_received": num(mob, "received"), "updates_accepted": num(mob, "accepted")})
                traj_kinds = sorted({(read_json(os.path.join(run(f"bandwidth_{l['level']}"), "counters.json")) or {})
                                     .get("trajectory", "?") for l in ds["bandwidth"]})
                rows.append([level["level"], f"{level['up_mbps']} / {level['down_mbps']}",
                             "yes" if c.get("delay_applied") else "no (no netem)", fmt(a and a["rmse_m"] * 100),
                             a["poses"] if a else "n/a", created if created is not None else "n/a",
                             received if received is not None else "n/a", inserted if inserted is not None else "n/a",
                             dropped if dropped is not None else "n/a", not_inserted if not_inserted is not None else "n/a",
                             f"{num(mob, 'accepted')}/{num(mob, 'received')}" if mob else "n/a"])
            body.line("Mobile and edge in two network namespaces joined by a veth pair; each end's egress shaped "
                      "with tc tbf (upload on the mobile side, download on the edge side) and, where the kernel "
                      "has sch_netem, 5 ms netem delay. ROS master and edge in the edge namespace; bag playback, "
                      "mobile and a pose recorder in the mobile namespace. ATE of the "
                      f"{' / '.join(traj_kinds)} trajectory.")
            body.line()
            body.table(["level", "up / down [Mbit/s]", "5 ms delay", "ATE RMSE [cm]", "poses", "KFs created (mobile)",
                        "KFs received (edge)", "KFs inserted (edge)", "dropped in transit", "sent, never inserted",
                        "updates accepted/received"], rows)
            if not all((c or {}).get("delay_applied") for c in
                       [read_json(os.path.join(run(f"bandwidth_{l['level']}"), "counters.json")) for l in ds["bandwidth"]]):
                body.line("The 5 ms delay could not be applied: this kernel has no sch_netem (`tc qdisc ... netem` "
                          "answers \"Specified qdisc kind is unknown\"), so only the rates are shaped.")
                body.line()
        else:
            body.line(f"not measured ({ds.get('bandwidth_skipped', 'not run')}).")
            body.line()

    # 6. Wire micro-benchmark
    wsec = Report(out)
    wsec.line("## KeyFrame and update on the wire (micro-benchmark)")
    wsec.line()
    if wire and wire.get("keyframe_bytes", {}).get("count"):
        kb = wire["keyframe_bytes"]
        rt = wire["keyframe_roundtrip_ms"]
        wsec.line(f"`wire_benchmark` on the first {wire['frames']} frames of `{os.path.basename(wire['dataset'])}` "
                  f"({wire['orb_features']} ORB features per frame): every KeyFrame the mobile session emits goes "
                  "through the bridge (`to_message`), `ros::serialization` and back (`from_message`); every 30 frames "
                  "the edge session builds a Local-Map update that takes the same round trip and is applied to an "
                  "empty map as the mobile applies one: staged off-line (`stage_update`: objects built, linked, BoW; "
                  "tracking keeps running) then swapped in (`install_update`: the only part tracking waits for).")
        wsec.line()
        rows = []
        for key, label, scale, unit in [
                ("keyframe_keypoints", "KeyFrame keypoints", 1, ""), ("keyframe_new_points", "KeyFrame new map points", 1, ""),
                ("keyframe_bytes", "KeyFrame wire size", 1e-3, " KB"), ("keyframe_serialize_ms", "KeyFrame serialize", 1, " ms"),
                ("keyframe_deserialize_ms", "KeyFrame deserialize", 1, " ms"),
                ("keyframe_roundtrip_ms", "KeyFrame serialize + deserialize", 1, " ms"),
                ("update_keyframes", "update KeyFrames", 1, ""), ("update_points", "update map points", 1, ""),
                ("update_bytes", "update wire size", 1e-3, " KB"), ("update_serialize_ms", "update serialize", 1, " ms"),
                ("update_deserialize_ms", "update deserialize", 1, " ms"),
                ("update_stage_ms", "Local-Map update staged off-line (tracking runs)", 1, " ms"),
                ("update_rebuild_ms", "Local-Map swapped in (tracking paused)", 1, " ms")]:
            s = wire.get(key) or {}
            if s.get("count"):
                rows.append([label, s["count"], fmt(s["mean"] * scale, ".2f", unit), fmt(s["median"] * scale, ".2f", unit),
                             fmt(s["p95"] * scale, ".2f", unit), fmt(s["max"] * scale, ".2f", unit)])
        wsec.table(["figure", "count", "mean", "median", "p95", "max"], rows)
        size_ok = kb["median"] <= 40e3
        time_ok = rt["median"] <= 2.0
        wsec.line(f"Target KeyFrame wire size <= 40 KB at 1000 features: median {kb['median'] / 1e3:.1f} KB, "
                  f"max {kb['max'] / 1e3:.1f} KB -> {verdict(size_ok)}; serialize + deserialize <= 2 ms: median "
                  f"{rt['median']:.2f} ms, p95 {rt['p95']:.2f} ms -> {verdict(time_ok)}.")
        wsec.line()
        rep.target("KeyFrame wire size <= 40 KB at 1000 features", f"median {kb['median'] / 1e3:.1f} KB", size_ok)
        rep.target("KeyFrame serialize + deserialize <= 2 ms", f"median {rt['median']:.2f} ms", time_ok)
    else:
        wsec.line("not measured (wire_benchmark did not run or failed; see wire_log.txt).")
        wsec.line()
        rep.target("KeyFrame wire size <= 40 KB at 1000 features", "n/a", None)
        rep.target("KeyFrame serialize + deserialize <= 2 ms", "n/a", None)

    long_run(manifest, out, rep, wsec, bench)
    bench["speed"] = speed.speed_section(rep, wsec, out, manifest)

    # Assemble: header, targets, per-dataset sections, wire section, what is not measured.
    m = manifest.get("machine", {})
    rep.line("# Edge-SLAM benchmark report")
    rep.line()
    added = "".join(f"; runs added {a['machine']['date']} ({fmt((a.get('bench_wall_s') or 0) / 60, '.1f')} min, "
                    f"commit `{a['machine']['commit'][:10]}`)" for a in manifest.get("added", []))
    rep.line(f"- date: {m.get('date', '?')}; `make bench` wall time {fmt((manifest.get('bench_wall_s') or 0) / 60, '.1f')} "
             f"min{added}")
    rep.line(f"- machine: {m.get('nproc', '?')} cores ({m.get('cpu_model', '?')}), {m.get('ram_gib', '?')} GiB RAM, "
             f"Linux {m.get('kernel', '?')}; load average at start {', '.join(f'{x:.2f}' for x in m.get('load_average_at_start', []))} "
             "(shared machine: timings are noisy, ratios come from one run)")
    rep.line(f"- commit measured: `{m.get('commit', '?')}` ({m.get('commit_subject', '')})"
             f"{' + uncommitted changes' if m.get('dirty') else ''}")
    rep.line(f"- datasets: {', '.join(d['name'] for d in manifest['datasets']) or 'none'}; "
             "command: `make bench` (scripts/bench/bench.py)")
    rep.line()
    rep.line("## Targets")
    rep.line()
    rep.table(["target", "measured", "verdict"], rep.targets)
    rep.md += body.md + wsec.md
    gaps = [f"{t} ({f})" for t, f, v in rep.targets if v == "not measured"]
    if not any(ds.get("bandwidth") for ds in manifest["datasets"]):
        gaps.append("bandwidth limits (paper Table 5: ip netns + veth + tc at 51/67, 20/20, 15/10 Mbps + 5 ms)")
    if not manifest.get("long_run"):
        gaps.append("long run (mobile RSS slope after warm-up on the long synthetic variant)")
    rep.line("## Not measured in this report")
    rep.line()
    rep.md += [f"- {g}" for g in gaps] or ["Nothing: every section above was measured."]
    rep.line()
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(rep.md) + "\n")
    bench["targets"] = [{"target": t, "measured": f, "verdict": v.strip("*")} for t, f, v in rep.targets]
    with open(os.path.join(out, "bench.json"), "w") as f:
        json.dump(bench, f, indent=2, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    print(f"report: {out}/report.md, bench.json")


if __name__ == "__main__":
    main()
