#!/usr/bin/env python3
"""Benchmark report: OUT/runs/ (written by bench.py) -> OUT/report.md, OUT/bench.json, OUT/*.png.

python3 -m bench.report --out <dir>   (venv python: evo for the ATE, matplotlib for the plots)

Sections follow the paper's evaluation (section 5), issue "Benchmark suite" and the robustness
issue (#13); every target in TARGETS gets PASS / MISS / not measured next to its figure. One
function per section (DATASET_SECTIONS run per dataset, then the wire and long-run sections).
Missing inputs (a crashed run, split mode not available, no stats CSV) give "not measured"
lines, never a crash.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import ate as ate_tool  # noqa: E402
from . import pipeline_stats  # noqa: E402
from . import scaling, speed  # noqa: E402
from .bench_data import cpu_percent, heap_series, net_rows, objects_beyond_map, proc_series, read_json  # noqa: E402
from edge_slam_common.tum import pose_seconds  # noqa: E402

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
    """bench.ate (evo APE, SE(3) alignment, the project's one association tolerance) with the
    aligned positions for the plot; None when the trajectory is missing or does not pair up."""
    if not os.path.isfile(trajectory):
        return None
    try:
        s, ref, est = ate_tool.evaluate(groundtruth, trajectory)
    except Exception as e:  # evo raises its own types for empty/unreadable files
        print(f"report: ATE of {trajectory}: {e}", file=sys.stderr)
        return None
    return {"rmse_m": s["ate_rmse_m"], "mean_m": s["ate_mean_m"], "std_m": s["ate_std_m"], "max_m": s["ate_max_m"],
            "poses": s["ate_pairs"], "ref_xyz": ref.positions_xyz, "est_xyz": est.positions_xyz}


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


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
    return save(fig, path)


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
    return save(fig, path)


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
    return save(fig, path)


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
    return save(fig, path)


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
        stamps = np.array(pose_seconds(traj))
        after = stamps[stamps > blank_range[1]]
        out["first_pose_after_blank_s"] = float(after[0] - blank_range[1]) if len(after) else None
    return out


# ---------------------------------------------------------------- targets

# key -> (label, threshold): a figure passes when it is <= its threshold. Labels may name the
# dataset ({name}). The issue each target comes from: paper/benchmark issue, #13 robustness, #14 split.
TARGETS = {
    "split_ate_ratio": ("Split ATE <= 1.1x monolithic ({name})", 1.1),
    "mobile_cpu_ratio": ("Mobile CPU-seconds split <= 0.5x monolithic ({name})", 0.5),
    "rebuild_ms": ("Local-Map rebuild (6-KeyFrame update) median <= 20 ms", 20.0),
    "upload_mbps": ("Mean upload <= 2 Mbps ({name})", 2.0),
    "download_mbps": ("Mean download <= 5 Mbps ({name})", 5.0),
    "keyframe_bytes": ("KeyFrame wire size <= 40 KB at 1000 features", 40e3),
    "keyframe_roundtrip_ms": ("KeyFrame serialize + deserialize <= 2 ms", 2.0),
    "mobile_rss_slope": ("Mobile RSS slope after warm-up <= 0.5 MB/min (split, long run)", 0.5),
    # issue #14 (the split on real data): tighter than the paper's figures above
    "mobile_cpu_ratio_14": ("Mobile CPU-seconds split <= 0.35x monolithic ({name}, issue #14)", 0.35),
    "fr1_upload_mbps": ("Mean upload <= 1.5 Mbps ({name}, issue #14)", 1.5),
    "fr1_download_mbps": ("Mean download <= 1 Mbps ({name}, issue #14)", 1.0),
    # issue #13 (fr1_rpy, monolithic runs in real time)
    "fr1_mono_worst_m": ("Every monolithic run <= 1.5 cm ({name}, {runs} runs)", 0.015),
    "fr1_mono_median_m": ("Monolithic median ATE <= 1.1 cm ({name}, {runs} runs)", 0.011),
    # issue #14 (fr1_rpy)
    "fr1_split_median_ratio": ("Split median final ATE <= 1.1x monolithic median ({name})", 1.1),
    "fr1_split_worst_ratio": ("Every split final ATE <= 1.5x monolithic median ({name})", 1.5),
    "fr1_online_median_m": ("Split online ATE median <= 1.5 cm ({name})", 0.015),
    "fr1_online_worst_m": ("Every split online ATE <= 2.5 cm ({name})", 0.025),
    "fr1_jump_worst_m": ("Largest online jump at an update <= 1 cm, every split run ({name})", 0.01),
    # issues #13 / #14 (synthetic_room)
    "synthetic_mono_worst_m": ("Every monolithic run <= 0.45 cm ({name}, {runs} runs)", 0.0045),
    "synthetic_split_median_ratio": ("Split median final ATE <= 1.2x monolithic median ({name})", 1.2),
    "synthetic_online_worst_m": ("Every split online ATE <= 1.0 cm ({name})", 0.010),
}


class Report:
    """Markdown lines, plus the targets summary (name, measured, verdict)."""

    def __init__(self, out_dir):
        self.out, self.md, self.targets = out_dir, [], []

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

    def check(self, key, figure, value, **names):
        """Target `key` of TARGETS: value <= threshold (None: not measured). Returns the verdict."""
        label, threshold = TARGETS[key]
        ok = None if value is None else value <= threshold
        self.target(label.format(**names), figure, ok)
        return ok


class Dataset:
    """What a dataset's sections share: its manifest entry, runs, output and report."""

    def __init__(self, out, ds, manifest, rep, body, bench, wire):
        self.out, self.ds, self.manifest, self.rep, self.body, self.wire = out, ds, manifest, rep, body, wire
        self.name, self.gt = ds["name"], os.path.join(ds["path"], "groundtruth.txt")
        self.ran = {r["variant"]: r for r in ds["runs"]}
        self.d = bench["datasets"].setdefault(self.name, {"seconds": ds["seconds"], "runs": self.ran})

    def run(self, variant):
        return os.path.join(self.out, "runs", self.name, variant)

    def section(self, title):
        """Starts a "### title" section of this dataset; returns the report to write it into."""
        self.body.line(f"### {title}")
        self.body.line()
        return self.body

    def metrics(self, variant):
        return read_json(os.path.join(self.run(variant), "metrics.json")) or {}

    def kind(self):
        """'fr1', 'synthetic' or None: which dataset-specific targets apply."""
        n = self.name.lower()
        return "fr1" if ("fr1" in n or "freiburg1" in n) else ("synthetic" if "synthetic" in n else None)


# ---------------------------------------------------------------- per-dataset sections

def section_intro(c):
    c.body.line(f"## {c.name}")
    c.body.line()
    c.body.line(f"{c.ds['seconds']:.1f} s of camera data, played in real time. Runs: " + ", ".join(
        f"{v} ({'ok' if r['exit_code'] == 0 else 'FAILED, exit %d' % r['exit_code']}, {r['wall_s']:.0f} s)"
        for v, r in c.ran.items()) + ".")
    c.body.line()


def section_accuracy(c):
    body = c.section("1. Accuracy (paper Table 2, Fig. 6)")
    acc, rows = {}, []
    for mode in MODES:
        m = c.metrics(mode)
        a = ate(c.gt, os.path.join(c.run(mode), "trajectory.txt")) if mode in c.ran else None
        acc[mode] = a
        c.d.setdefault("accuracy", {})[mode] = None if a is None else {
            k: v for k, v in a.items() if not k.endswith("_xyz")} | {
            "frames": m.get("frames"), "frames_tracked": m.get("frames_tracked"),
            "keyframes": m.get("keyframes"), "keyframes_created": m.get("keyframes_created"),
            "loops_closed": m.get("loops_closed")}
        # Created by tracking (the monolithic map keeps fewer after culling; the split mobile's count is its created ones).
        rows.append([mode, f"{m.get('frames_tracked', 'n/a')}/{m.get('frames', 'n/a')}",
                     m["keyframes_created"] if "keyframes_created" in m else f"{m.get('keyframes', 'n/a')} kept",
                     m.get("loops_closed", "n/a")] +
                    ([fmt(a["rmse_m"] * 100), fmt(a["mean_m"] * 100), fmt(a["std_m"] * 100), a["poses"]]
                     if a else ["not measured"] * 4))
    body.table(["mode", "frames tracked / received", "keyframes created", "loops", "ATE RMSE [cm]", "mean [cm]",
                "std [cm]", "poses"], rows)
    body.line("Frames received: the monolithic runner reads every associated colour/depth pair; the split "
              "mobile takes what rosbag plays in real time. Split ATE is of its final "
              "trajectory (frames re-anchored on the edge's final KeyFrames, `make eval MODE=split`).")
    body.line()
    ratio = None
    if acc["monolithic"] and acc["split"]:
        ratio = acc["split"]["rmse_m"] / acc["monolithic"]["rmse_m"]
        figure = f"split {acc['split']['rmse_m'] * 100:.2f} cm / monolithic {acc['monolithic']['rmse_m'] * 100:.2f} cm = {ratio:.2f}x"
        c.d["accuracy"]["split_over_monolithic"] = ratio
    else:
        figure = "split run " + ("missing" if not acc["split"] else "ok") + ", monolithic " + \
                 ("missing" if not acc["monolithic"] else "ok")
    ok = c.rep.check("split_ate_ratio", figure, ratio, name=c.name)
    body.line(f"Target split ATE <= 1.1x monolithic: {figure} -> {verdict(ok)}")
    body.line()
    if plot_trajectories(os.path.join(c.out, f"trajectory_{c.name}.png"), c.name, acc):
        body.image(f"trajectory_{c.name}.png", f"{c.name} trajectories")


MODULES = [("tracking", "tracking_ms"), ("local mapping (per KeyFrame)", "local_mapping_ms"),
           ("local BA", "local_ba_ms"), ("loop detection", "loop_detection_ms"),
           ("loop correction", "loop_correction_ms"), ("full BA", "full_ba_ms")]


def section_latency(c):
    body = c.section("2. Module latency (paper Fig. 7)")
    rows = []
    for mode in MODES:
        m = c.metrics(mode)
        for label, key in MODULES:
            s = m.get(key)
            c.d.setdefault("latency_ms", {}).setdefault(mode, {})[key] = s
            if s and s.get("count"):
                rows.append([mode, label, s.get("count", "n/a"), fmt(s.get("mean")), fmt(s.get("median")),
                             fmt(s.get("p95")), fmt(s.get("max"))])
    if rows:
        body.table(["mode", "module", "count", "mean [ms]", "median [ms]", "p95 [ms]", "max [ms]"], rows)
    else:
        body.line("not measured (no metrics.json)")
        body.line()
    series = {mode: pipeline_stats.frame_times(c.run(mode)) for mode in MODES}
    t0 = c.ds["fast_turn"][0] - c.ds.get("fast_turn_from_start", [0])[0]
    if plot_tracking(os.path.join(c.out, f"tracking_{c.name}.png"), c.name, series, t0, c.ds["fast_turn"]):
        body.image(f"tracking_{c.name}.png", f"{c.name} tracking latency")
    missing = [m for m, s in series.items() if s[0] is None]
    if missing:
        body.line(f"Per-frame tracking latency not available for: {', '.join(missing)} "
                  "(needs frame_times.csv or per-frame rows in mobile_stats.csv).")
        body.line()


def section_cpu_memory(c):
    body = c.section("3. Mobile CPU and memory (paper Fig. 8)")
    procs, rows = {}, []
    for mode in MODES:
        for role, p in proc_series(c.run(mode)).items():
            label = f"{role} {mode}" if role == "mobile" else f"edge ({mode})"
            procs[label] = p
            tc, pct = cpu_percent(p["t"], p["cpu_s"])
            c.d.setdefault("cpu_memory", {})[label] = {
                "cpu_seconds": float(p["cpu_s"][-1]), "mean_cpu_percent": float(pct.mean()) if len(pct) else None,
                "peak_cpu_percent": float(pct.max()) if len(pct) else None,
                "peak_rss_mb": float(p["rss_mb"].max()), "final_rss_mb": float(p["rss_mb"][-1]),
                "samples": int(len(p["t"])), "sample_hz": float((len(p["t"]) - 1) / max(p["t"][-1], 1e-9))}
            s = c.d["cpu_memory"][label]
            rows.append([label, fmt(s["cpu_seconds"], ".1f"), fmt(s["mean_cpu_percent"], ".0f"),
                         fmt(s["peak_cpu_percent"], ".0f"), fmt(s["peak_rss_mb"], ".0f"),
                         fmt(s["final_rss_mb"], ".0f"), f"{s['samples']} @ {s['sample_hz']:.1f} Hz"])
    if rows:
        body.line("CPU-seconds = user + system time of the whole process life (psutil): vocabulary loading, "
                  "tracking and, in monolithic mode, Local-Mapping catching up and the final global BA "
                  "after the camera data ended.")
        body.line()
        body.table(["process", "CPU-seconds", "mean CPU %", "peak CPU % (1 s)", "peak RSS [MB]",
                    "final RSS [MB]", "samples"], rows)
    mono, split = procs.get("mobile monolithic"), procs.get("mobile split")
    ratio = None
    if mono is not None and split is not None:
        ratio = split["cpu_s"][-1] / mono["cpu_s"][-1]
        figure = f"split mobile {split['cpu_s'][-1]:.1f} CPU-s / monolithic {mono['cpu_s'][-1]:.1f} CPU-s = {ratio:.2f}x"
        c.d["cpu_memory"]["mobile_cpu_ratio"] = ratio
    else:
        figure = "needs both a monolithic and a split run with samples"
    ok = c.rep.check("mobile_cpu_ratio", figure, ratio, name=c.name)
    ok_14 = c.rep.check("mobile_cpu_ratio_14", figure, ratio, name=c.name)
    body.line(f"Target mobile CPU-seconds (split) <= 0.5x monolithic: {figure} -> {verdict(ok)}; "
              f"issue #14's <= 0.35x: {verdict(ok_14)}")
    body.line()
    if plot_cpu_memory(os.path.join(c.out, f"cpu_memory_{c.name}.png"), c.name, procs):
        body.image(f"cpu_memory_{c.name}.png", f"{c.name} CPU and memory")


def section_pipeline(c):
    body = c.section("4. Map-update pipeline (paper Table 4)")
    pipe = {v: pipeline_stats.summarize(c.run(v)) for v in ("split", "split_controller") if v in c.ran}
    c.d["map_update_pipeline"] = pipe
    ctrl = c.ran.get("split_controller", {}).get("controller_window")
    rows = pipeline_stats.table_rows(pipe)
    if rows:
        turn = c.ds.get("fast_turn_from_start", [0, 0])
        body.line("The controller run (`planner_example`) disables updates from 1.0 s before to 0.5 s after "
                  f"the fastest turn in the ground truth (t = {turn[0]:.2f}-{turn[1]:.2f} s from the start, "
                  f"peak {c.ds['fast_turn_peak_deg_s']:.0f} deg/s)" + ("" if ctrl else " - it did not run") + ".")
        body.line()
        body.table(["figure", "split", "split + controller"], rows)
    else:
        body.line("not measured: the split runs left no mobile_stats.csv / edge_stats.csv.")
        body.line()
    rebuild = pipeline_stats.rebuild_median(pipe.get("split"))
    source = "split run (mobile_stats.csv)"
    if rebuild is None and c.wire and c.wire.get("update_rebuild_ms", {}).get("count"):
        rebuild, source = c.wire["update_rebuild_ms"]["median"], "wire micro-benchmark (install_update)"
    if c.name == c.manifest["datasets"][0]["name"]:
        figure = "n/a" if rebuild is None else f"median {rebuild:.1f} ms ({source})"
        ok = c.rep.check("rebuild_ms", figure, rebuild)
        body.line(f"Target Local-Map rebuild from a 6-KeyFrame update, median <= 20 ms: {figure} -> {verdict(ok)}")
        body.line()


def section_network(c):
    body = c.section("5. Network (paper Fig. 9)")
    net = net_rows(c.run("split"))
    summary = network_summary(net, c.ds["seconds"])
    c.d["network"] = summary
    if summary:
        rows = [[t, v["messages"], fmt(v["bytes_mean"] / 1e3, ".1f"), fmt(v["bytes_median"] / 1e3, ".1f"),
                 fmt(v["bytes_max"] / 1e3, ".1f"), fmt(v["bytes_total"] / 1e6, ".2f")]
                for t, v in summary["per_topic"].items()]
        body.table(["topic", "messages", "mean [KB]", "median [KB]", "max [KB]", "total [MB]"], rows)
        up_ok = c.rep.check("upload_mbps", f"{summary['upload_mbps']:.3f} Mbps", summary["upload_mbps"], name=c.name)
        down_ok = c.rep.check("download_mbps", f"{summary['download_mbps']:.3f} Mbps", summary["download_mbps"],
                              name=c.name)
        body.line(f"Mean over the {c.ds['seconds']:.1f} s sequence: upload {summary['upload_mbps']:.3f} Mbps "
                  f"(target <= 2: {verdict(up_ok)}), download {summary['download_mbps']:.3f} Mbps "
                  f"(target <= 5: {verdict(down_ok)}). 1 KB = 1000 bytes.")
        if c.kind() == "fr1":
            up14 = c.rep.check("fr1_upload_mbps", f"{summary['upload_mbps']:.3f} Mbps", summary["upload_mbps"],
                               name=c.name)
            down14 = c.rep.check("fr1_download_mbps", f"{summary['download_mbps']:.3f} Mbps",
                                 summary["download_mbps"], name=c.name)
            body.line(f"Issue #14's targets on fr1: upload <= 1.5 Mbps {verdict(up14)}, download <= 1 Mbps "
                      f"{verdict(down14)}.")
        body.line()
    else:
        body.line("not measured: no topic recording from a split run.")
        body.line()
        c.rep.check("upload_mbps", "no split run", None, name=c.name)
        c.rep.check("download_mbps", "no split run", None, name=c.name)
    if plot_network(os.path.join(c.out, f"network_{c.name}.png"), c.name, net):
        body.image(f"network_{c.name}.png", f"{c.name} network")


def blank_range(ds):
    """(first, last) blanked stamp of the dataset's blank copy, or None."""
    if ds.get("blank_range"):
        return tuple(ds["blank_range"])
    parts = ds.get("blank", "").split()  # manifests of older benches: "<n> blank frames <lo>-<hi>"
    if len(parts) >= 4 and parts[1] == "blank":
        lo, hi = parts[3].split("-")
        return float(lo), float(hi)
    return None


def section_relocalization(c):
    body = c.section("6. Relocalization with blanked frames (paper Table 3)")
    rows = []
    for mode in MODES:
        r = relocalization(c.run(f"{mode}_blank"), blank_range(c.ds)) if f"{mode}_blank" in c.ran else None
        c.d.setdefault("relocalization", {})[mode] = r
        if r:
            a = ate(c.gt, os.path.join(c.run(f"{mode}_blank"), "trajectory.txt"))
            r["ate_rmse_m"] = a["rmse_m"] if a else None
            rows.append([mode, r["times_lost"], r["relocalizations"], fmt(r.get("first_pose_after_blank_s"), ".2f", " s"),
                         f"{r['frames_tracked']}/{r['frames']}", fmt(a["rmse_m"] * 100 if a else None)])
        else:
            rows.append([mode] + ["not measured"] * 5)
    blank = c.ds.get("blank", "")
    body.line(f"Copy with {blank} (black colour images, depth kept)." if blank else "Not run.")
    body.line()
    body.table(["mode", "times lost", "relocalizations", "first pose after the blank run", "frames tracked",
                "ATE RMSE [cm]"], rows)


def section_bandwidth(c):
    body = c.section("7. Bandwidth limits (paper Table 5)")
    if not c.ds.get("bandwidth"):
        body.line(f"not measured ({c.ds.get('bandwidth_skipped', 'not run')}).")
        body.line()
        return
    rows, c.d["bandwidth"] = [], []
    counters = {l["level"]: read_json(os.path.join(c.run(f"bandwidth_{l['level']}"), "counters.json")) or {}
                for l in c.ds["bandwidth"]}
    num = lambda dct, k: int(dct[k]) if str(dct.get(k, "")).isdigit() else None  # noqa: E731
    na = lambda v: "n/a" if v is None else v  # noqa: E731
    for level in c.ds["bandwidth"]:
        cnt = counters[level["level"]]
        a = ate(c.gt, os.path.join(c.run(f"bandwidth_{level['level']}"), "trajectory.txt"))
        mob, edge = cnt.get("mobile") or {}, cnt.get("edge") or {}
        created, received, inserted = num(mob, "keyframes_created"), num(edge, "received"), num(edge, "inserted")
        dropped = created - received if created is not None and received is not None else None
        not_inserted = created - inserted if created is not None and inserted is not None else None
        c.d["bandwidth"].append({**level, "delay_applied": cnt.get("delay_applied"), "ate_rmse_m": a and a["rmse_m"],
                                 "poses": a and a["poses"], "keyframes_created": created,
                                 "keyframes_received": received, "keyframes_inserted": inserted,
                                 "keyframes_dropped_in_transit": dropped, "keyframes_not_inserted": not_inserted,
                                 "updates_received": num(mob, "received"), "updates_accepted": num(mob, "accepted")})
        rows.append([level["level"], f"{level['up_mbps']} / {level['down_mbps']}",
                     "yes" if cnt.get("delay_applied") else "no (no netem)", fmt(a and a["rmse_m"] * 100),
                     a["poses"] if a else "n/a", na(created), na(received), na(inserted), na(dropped), na(not_inserted),
                     f"{num(mob, 'accepted')}/{num(mob, 'received')}" if mob else "n/a"])
    traj_kinds = sorted({cnt.get("trajectory", "?") for cnt in counters.values()})
    body.line("Mobile and edge in two network namespaces joined by a veth pair; each end's egress shaped "
              "with tc tbf (upload on the mobile side, download on the edge side) and, where the kernel "
              "has sch_netem, 5 ms netem delay. ROS master and edge in the edge namespace; bag playback, "
              "mobile and a pose recorder in the mobile namespace. ATE of the "
              f"{' / '.join(traj_kinds)} trajectory.")
    body.line()
    body.table(["level", "up / down [Mbit/s]", "5 ms delay", "ATE RMSE [cm]", "poses", "KFs created (mobile)",
                "KFs received (edge)", "KFs inserted (edge)", "dropped in transit", "sent, never inserted",
                "updates accepted/received"], rows)
    if not all(cnt.get("delay_applied") for cnt in counters.values()):
        body.line("The 5 ms delay could not be applied: this kernel has no sch_netem (`tc qdisc ... netem` "
                  "answers \"Specified qdisc kind is unknown\"), so only the rates are shaped.")
        body.line()


def spread(values):
    """median, worst, spread (max - min) and how many exceed 2x the median, of a list of figures."""
    v = np.array([x for x in values if x is not None], float)
    if not len(v):
        return None
    med = float(np.median(v))
    return {"runs": int(len(v)), "median": med, "worst": float(v.max()), "best": float(v.min()),
            "spread": float(v.max() - v.min()), "over_2x_median": int((v > 2 * med).sum()), "values": v.tolist()}


def robust_runs(c):
    """[(k, monolithic metrics, split metrics)] of the robustness pairs that ran."""
    pairs = []
    for k in range(1, int(c.ds.get("robust_runs", 0)) + 1):
        mono, split = f"robust_monolithic_{k}", f"robust_split_{k}"
        if mono in c.ran or split in c.ran:
            pairs.append((k, c.metrics(mono) if mono in c.ran else {}, c.metrics(split) if split in c.ran else {}))
    return pairs


def section_robustness(c):
    """Issue #13: N back-to-back pairs of `make eval` (monolithic, then split): the spread of the
    final ATE (both modes) and of the split's online ATE and largest jump at an update."""
    body = c.section("8. Robustness: repeated runs (issue #13)")
    pairs = robust_runs(c)
    if not pairs:
        body.line("not run (`make bench BENCH_ARGS=\"--only robustness --robust-runs 5\"`).")
        body.line()
        return
    cm = lambda v: "n/a" if v is None else f"{v * 100:.2f}"  # noqa: E731
    rows = [[k, cm(m.get("ate_rmse_m")), cm(m.get("ate_online_rmse_m")), cm(s.get("ate_rmse_m")),
             cm(s.get("ate_online_rmse_m")),
             cm(s.get("update_jump_max_m")), f"{m.get('times_lost', 'n/a')} / {s.get('times_lost', 'n/a')}"]
            for k, m, s in pairs]
    body.line(f"{len(pairs)} pairs, each `make eval MODE=monolithic` then `MODE=split` back to back, in real time; "
              "every ATE from bench.ate (evo, the same association tolerance for the final and online "
              "trajectories).")
    body.line()
    body.table(["pair", "monolithic final ATE [cm]", "monolithic online ATE [cm]", "split final ATE [cm]",
                "split online ATE [cm]",
                "largest online jump at an update [cm]", "times lost (mono / split)"], rows)
    figures = {"monolithic final": spread([m.get("ate_rmse_m") for _, m, _ in pairs]),
               "monolithic online": spread([m.get("ate_online_rmse_m") for _, m, _ in pairs]),
               "split final": spread([s.get("ate_rmse_m") for _, _, s in pairs]),
               "split online": spread([s.get("ate_online_rmse_m") for _, _, s in pairs]),
               "split largest jump at an update": spread([s.get("update_jump_max_m") for _, _, s in pairs])}
    c.d["robustness"] = figures
    body.table(["figure", "runs", "median [cm]", "worst [cm]", "spread (max - min) [cm]", "runs > 2x median"],
               [[label, f["runs"], cm(f["median"]), cm(f["worst"]), cm(f["spread"]), f["over_2x_median"]]
                if f else [label, 0, "n/a", "n/a", "n/a", "n/a"] for label, f in figures.items()])
    robustness_targets(c, figures)


def robustness_targets(c, f):
    """The dataset-specific targets of issues #13 / #14 on the robustness runs."""
    mono, split, online, jump = (f["monolithic final"], f["split final"], f["split online"],
                                 f["split largest jump at an update"])
    cm = lambda v: f"{v * 100:.2f} cm"  # noqa: E731
    kind = c.kind()
    runs = mono["runs"] if mono else 0
    ratio_of = lambda a, key: (a[key] / mono["median"]) if a and mono and mono["median"] > 0 else None  # noqa: E731
    if kind == "fr1":
        c.rep.check("fr1_mono_worst_m", f"worst {cm(mono['worst'])}" if mono else "no run",
                    mono and mono["worst"], name=c.name, runs=runs)
        c.rep.check("fr1_mono_median_m", f"median {cm(mono['median'])}" if mono else "no run",
                    mono and mono["median"], name=c.name, runs=runs)
        r = ratio_of(split, "median")
        c.rep.check("fr1_split_median_ratio", "n/a" if r is None else f"{cm(split['median'])} / {cm(mono['median'])} "
                    f"= {r:.2f}x", r, name=c.name)
        r = ratio_of(split, "worst")
        c.rep.check("fr1_split_worst_ratio", "n/a" if r is None else f"worst {cm(split['worst'])} = {r:.2f}x", r,
                    name=c.name)
        c.rep.check("fr1_online_median_m", f"median {cm(online['median'])}" if online else "n/a",
                    online and online["median"], name=c.name)
        c.rep.check("fr1_online_worst_m", f"worst {cm(online['worst'])}" if online else "n/a",
                    online and online["worst"], name=c.name)
        c.rep.check("fr1_jump_worst_m", f"worst {cm(jump['worst'])}" if jump else "n/a", jump and jump["worst"],
                    name=c.name)
    elif kind == "synthetic":
        c.rep.check("synthetic_mono_worst_m", f"worst {cm(mono['worst'])}" if mono else "no run",
                    mono and mono["worst"], name=c.name, runs=runs)
        r = ratio_of(split, "median")
        c.rep.check("synthetic_split_median_ratio", "n/a" if r is None else f"{cm(split['median'])} / "
                    f"{cm(mono['median'])} = {r:.2f}x", r, name=c.name)
        c.rep.check("synthetic_online_worst_m", f"worst {cm(online['worst'])}" if online else "n/a",
                    online and online["worst"], name=c.name)


DATASET_SECTIONS = [section_intro, section_accuracy, section_latency, section_cpu_memory, section_pipeline,
                    section_network, section_relocalization, section_bandwidth, section_robustness]


# ---------------------------------------------------------------- once per report

WIRE_ROWS = [("keyframe_keypoints", "KeyFrame keypoints", 1, ""), ("keyframe_new_points", "KeyFrame new map points", 1, ""),
             ("keyframe_bytes", "KeyFrame wire size", 1e-3, " KB"), ("keyframe_serialize_ms", "KeyFrame serialize", 1, " ms"),
             ("keyframe_deserialize_ms", "KeyFrame deserialize", 1, " ms"),
             ("keyframe_roundtrip_ms", "KeyFrame serialize + deserialize", 1, " ms"),
             ("update_keyframes", "update KeyFrames", 1, ""), ("update_points", "update map points", 1, ""),
             ("update_bytes", "update wire size", 1e-3, " KB"), ("update_serialize_ms", "update serialize", 1, " ms"),
             ("update_deserialize_ms", "update deserialize", 1, " ms"),
             ("update_stage_ms", "Local-Map update staged off-line (tracking runs)", 1, " ms"),
             ("update_rebuild_ms", "Local-Map swapped in (tracking paused)", 1, " ms")]


def section_wire(wire, rep, section):
    section.line("## KeyFrame and update on the wire (micro-benchmark)")
    section.line()
    if not (wire and wire.get("keyframe_bytes", {}).get("count")):
        section.line("not measured (wire_benchmark did not run or failed; see wire_log.txt).")
        section.line()
        rep.check("keyframe_bytes", "n/a", None)
        rep.check("keyframe_roundtrip_ms", "n/a", None)
        return
    kb, rt = wire["keyframe_bytes"], wire["keyframe_roundtrip_ms"]
    section.line(f"`wire_benchmark` on the first {wire['frames']} frames of `{os.path.basename(wire['dataset'])}` "
                 f"({wire['orb_features']} ORB features per frame): every KeyFrame the mobile session emits goes "
                 "through the bridge (`to_message`), `ros::serialization` and back (`from_message`); every 30 frames "
                 "the edge session builds a Local-Map update that takes the same round trip and is applied to an "
                 "empty map as the mobile applies one: staged off-line (`stage_update`: objects built, linked, BoW; "
                 "tracking keeps running) then swapped in (`install_update`: the only part tracking waits for).")
    section.line()
    rows = []
    for key, label, scale, unit in WIRE_ROWS:
        s = wire.get(key) or {}
        if s.get("count"):
            rows.append([label, s["count"], fmt(s["mean"] * scale, ".2f", unit), fmt(s["median"] * scale, ".2f", unit),
                         fmt(s["p95"] * scale, ".2f", unit), fmt(s["max"] * scale, ".2f", unit)])
    section.table(["figure", "count", "mean", "median", "p95", "max"], rows)
    size_ok = rep.check("keyframe_bytes", f"median {kb['median'] / 1e3:.1f} KB", kb["median"])
    time_ok = rep.check("keyframe_roundtrip_ms", f"median {rt['median']:.2f} ms", rt["median"])
    section.line(f"Target KeyFrame wire size <= 40 KB at 1000 features: median {kb['median'] / 1e3:.1f} KB, "
                 f"max {kb['max'] / 1e3:.1f} KB -> {verdict(size_ok)}; serialize + deserialize <= 2 ms: median "
                 f"{rt['median']:.2f} ms, p95 {rt['p95']:.2f} ms -> {verdict(time_ok)}.")
    section.line()


# ---------------------------------------------------------------- long run (RSS slope)

WARM_UP_S = 120.0


def slope_after_warm_up(t, mb, seconds, min_samples=20):
    """MB/min of a least-squares line through the samples from WARM_UP_S after the process
    started to the end of the camera data (the final global BA after it is not steady state)."""
    sel = (t >= WARM_UP_S) & (t <= seconds)
    if sel.sum() < min_samples:
        return None
    return float(np.polyfit(t[sel] / 60.0, mb[sel], 1)[0])


def rss_slope(p, seconds):
    return slope_after_warm_up(p["t"], p["rss_mb"], seconds)


def section_long_run(manifest, out, rep, section, bench):
    entry = manifest.get("long_run")
    section.line("## Long run: mobile memory over 10+ minutes")
    section.line()
    if not entry:
        why = manifest.get("long_run_skipped", "not run")
        section.line(f"not measured ({why}).")
        section.line()
        rep.check("mobile_rss_slope", f"not measured: {why}", None)
        return
    procs, rows, slopes, heap_slopes = {}, [], {}, {}
    for mode in MODES:
        run_dir = os.path.join(out, "runs", entry["name"], f"long_{mode}")
        series = proc_series(run_dir)
        for role, p in series.items():
            label = f"{role} {mode}" if role == "mobile" else f"edge ({mode})"
            procs[label] = p
            slope = rss_slope(p, entry["seconds"])
            slopes[label] = slope
            # The live heap (what the node keeps allocated), every 10 s: a leak shows here, the
            # allocator's kept pages and non-heap pages do not (split/memory_row.h). The split's
            # nodes write it; the monolithic process does not.
            heap = heap_series(run_dir, role) if mode == "split" else None
            heap_slope, beyond = None, "n/a"
            if heap is not None:
                heap_slope = slope_after_warm_up(heap["t"], heap["in_use_mb"], entry["seconds"], min_samples=5)
                heap_slopes[label] = heap_slope
                beyond = objects_beyond_map(heap)
            rows.append([label, fmt(p["cpu_s"][-1], ".1f"), fmt(p["rss_mb"].max(), ".0f"), fmt(slope, ".2f", " MB/min"),
                         fmt(heap_slope, ".2f", " MB/min"), beyond])
    bench["long_run"] = {"seconds": entry["seconds"], "rss_slope_mb_per_min": slopes,
                         "heap_in_use_slope_mb_per_min": heap_slopes, "warm_up_s": WARM_UP_S}
    section.line(f"`{entry['name']}`: {entry['seconds'] / 60:.1f} min of camera data (the embedded sequence's closed "
                 f"path driven {entry.get('laps', 20)} times at 15 fps, bench.loop_sequence; the split plays it live "
                 "from the folder with tum_player). RSS slope = least-squares "
                 f"line through the samples from {WARM_UP_S:.0f} s after start to the end of the camera data. "
                 "Live heap = what the mobile's process keeps allocated (glibc's own accounting, a reading every "
                 "10 s in mobile_stats.csv), same window: RSS also counts the free pages the allocator keeps and "
                 "non-heap pages, so a leak shows in both slopes, fragmentation in RSS only. Map objects beyond "
                 "the map = KeyFrames / points alive in the node's process minus those its map holds (the "
                 "mobile's Local-Map, the edge's Global-Map), the largest reading and the last: tracking's last "
                 "frame and an update being built or installed hold some for a moment; a count that grows is a "
                 "leak of map objects.")
    section.line()
    section.table(["process", "CPU-seconds", "peak RSS [MB]", "RSS slope after warm-up", "live heap slope",
                   "map objects beyond the map, max (last)"], rows)
    ran = {r["variant"] for r in entry.get("runs", [])}
    if "long_split" not in ran:
        section.line("Split mode on the long sequence: **not measured** (`make bench BENCH_ARGS=\"--add --only long "
                     "--long-modes split\"` adds it).")
        section.line()
    slope = slopes.get("mobile split")
    rep.check("mobile_rss_slope", "not measured: no split long run" if slope is None else
              f"{slope:.2f} MB/min (live heap {fmt(heap_slopes.get('mobile split'), '.2f')} MB/min; monolithic: "
              f"{fmt(slopes.get('mobile monolithic'), '.2f')} MB/min)", slope)
    if plot_cpu_memory(os.path.join(out, "cpu_memory_long.png"), entry["name"], procs):
        section.image("cpu_memory_long.png", "long run CPU and memory")


def header(rep, manifest):
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
             "command: `make bench` (python3 -m bench.bench)")
    rep.line()
    rep.line("## Targets")
    rep.line()
    rep.table(["target", "measured", "verdict"], rep.targets)


def not_measured(rep, manifest):
    gaps = [f"{t} ({f})" for t, f, v in rep.targets if v == "not measured"]
    if not any(ds.get("bandwidth") for ds in manifest["datasets"]):
        gaps.append("bandwidth limits (paper Table 5: ip netns + veth + tc at 51/67, 20/20, 15/10 Mbps + 5 ms)")
    if not manifest.get("long_run"):
        gaps.append("long run (mobile RSS slope after warm-up on the long synthetic variant)")
    if not manifest.get("scaling"):
        gaps.append("scaling (one edge with 1, 2, 3 mobiles; " + manifest.get("scaling_skipped", "not asked for") + ")")
    rep.line("## Not measured in this report")
    rep.line()
    rep.md += [f"- {g}" for g in gaps] or ["Nothing: every section above was measured."]
    rep.line()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    out = os.path.abspath(args.out)
    manifest = read_json(os.path.join(out, "manifest.json")) or {"datasets": [], "machine": {}}
    wire = read_json(os.path.join(out, "wire.json"))
    bench = {"machine": manifest.get("machine"), "bench_wall_s": manifest.get("bench_wall_s"), "datasets": {},
             "wire": wire}
    rep, body, tail = Report(out), Report(out), Report(out)  # the targets summary goes on top of the sections
    for ds in manifest["datasets"]:
        c = Dataset(out, ds, manifest, rep, body, bench, wire)
        for section in DATASET_SECTIONS:
            section(c)
    section_wire(wire, rep, tail)
    section_long_run(manifest, out, rep, tail, bench)
    bench["speed"] = speed.speed_section(rep, tail, out, manifest)
    bench["scaling"] = scaling.scaling_section(tail, out, manifest)
    header(rep, manifest)
    rep.md += body.md + tail.md
    not_measured(rep, manifest)
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(rep.md) + "\n")
    bench["targets"] = [{"target": t, "measured": f, "verdict": v.strip("*")} for t, f, v in rep.targets]
    with open(os.path.join(out, "bench.json"), "w") as f:
        json.dump(bench, f, indent=2, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o))
    print(f"report: {out}/report.md, bench.json")


if __name__ == "__main__":
    main()
