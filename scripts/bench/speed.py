"""Speed section of the benchmark (issue 15): per-stage tracking CPU, ORB extraction against
cv::ORB, local BA, the edge's KeyFrame throughput and the split mobile's tracking wall p99.

Runs (run_speed, from bench.py, variant "speed"), per dataset, into OUT/speed/<dataset>/:
  tracking_<k>/  scripts/eval.sh with --no-mapping --pace none (tracking only, flat out),
                 SPEED_TRACKING_RUNS times (default 3): metrics.json has the tracking thread's
                 CPU per frame, whole and per stage (util/stage_clock.h)
  orb.json       orb_benchmark --cv-threads 1: ours and cv::ORB interleaved in one process, CPU
                 time; cv::ORB is asked for as many features as ours returns on average
  stream.bin     keyframe_stream record: the KeyFrame records the mobile makes on the sequence
                 (derived from the dataset: lives in OUT only, never commit it)
  edge.json      keyframe_stream replay --mode sequential --cores 1: KeyFrames / s through
                 Local-Mapping, each with the full treatment, on one core; the first
                 SPEED_EDGE_KEYFRAMES records (default 150; 0 = all: on fr1_rpy the whole stream,
                 530 KeyFrames whose windows and loop closures grow with it, takes ~15 min)
The local BA figures and the split tracking p99 come from the monolithic and split runs of the
same bench (runs/<dataset>/{monolithic,split}).

speed_section (from report.py) writes the section and the targets, each PASS / MISS /
not measured. Timings on a shared machine move with its load: the thread-CPU figures move
less than wall time, and the ORB figure is a ratio within one process.
"""
import hashlib
import json
import os
import subprocess
import sys
import time

from .bench_data import read_json as _read

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
TOOLS = os.path.join(ROOT, ".ws/devel/lib/edge_slam_common")
STAGES = ["extract", "match", "pose", "local_map", "keyframe"]


def phases():
    """Progress lines per dataset: the tracking runs, ORB, record, replay."""
    return int(os.environ.get("SPEED_TRACKING_RUNS", "3")) + 3


TARGETS = {"tracking_cpu_median_ms": 12.0, "tracking_cpu_p95_ms": 18.0, "split_tracking_p99_ms": 30.0,
           "orb_ratio": 1.0, "local_ba_median_ms": 60.0, "local_ba_p95_ms": 150.0, "edge_keyframes_per_s": 5.0}


def speed_dir(out_dir, dataset):
    return os.path.join(out_dir, "speed", os.path.basename(dataset.rstrip("/")))


def camera_and_vocabulary(dataset):
    """What scripts/eval.sh picks for this folder (run a tracking pass first: it trains the
    vocabulary into results/cache/ when the dataset has none)."""
    camera = os.path.join(dataset, "camera.yaml")
    name = os.path.basename(dataset.rstrip("/"))
    if not os.path.isfile(camera) and ("fr1" in name or "freiburg1" in name):
        camera = os.path.join(ROOT, "config/camera_tum1.yaml")
    synthetic = os.path.realpath(os.path.join(ROOT, "bags/synthetic_room"))
    if os.path.realpath(dataset) == synthetic:
        vocabulary = os.path.join(ROOT, "bags/vocabulary_synthetic.bin")
    else:
        key = hashlib.sha1((os.path.realpath(dataset) + "\n").encode()).hexdigest()[:12]
        vocabulary = os.path.join(ROOT, "results/cache", f"vocabulary-{name}-{key}.bin")
    return camera, vocabulary


def _run(progress, label, cmd, log_path, env=None, expected_s=60):
    progress.start(label)
    t0 = time.time()
    with open(log_path, "w") as log:
        proc = subprocess.Popen(cmd, cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, env=env)
        while proc.poll() is None:
            progress.show(f"{time.time() - t0:4.0f} s / ~{expected_s:.0f} s")
            time.sleep(1.0)
    progress.done("ok" if proc.returncode == 0 else f"FAILED (exit {proc.returncode}, see {os.path.relpath(log_path, ROOT)})")
    return proc.returncode


def run_speed(progress, out_dir, dataset, seconds, tracking_runs=None):
    """The speed measurements of one dataset; returns a manifest entry."""
    d = speed_dir(out_dir, dataset)
    os.makedirs(d, exist_ok=True)
    runs = int(tracking_runs or os.environ.get("SPEED_TRACKING_RUNS", "3"))
    codes = {}
    for k in range(runs):
        run_dir = os.path.join(d, f"tracking_{k}")
        env = dict(os.environ, DATASET=dataset, MODE="monolithic", OUT=run_dir,
                   EDGE_SLAM_ARGS=(os.environ.get("EDGE_SLAM_ARGS", "") + " --no-mapping --pace none").strip())
        codes[f"tracking_{k}"] = _run(progress, f"{os.path.basename(dataset)} speed: tracking only {k + 1}/{runs}",
                                      ["bash", "scripts/eval.sh"], os.path.join(d, f"tracking_{k}.log"), env,
                                      seconds * 0.7 + 10)
    camera, vocabulary = camera_and_vocabulary(dataset)
    codes["orb"] = _run(progress, f"{os.path.basename(dataset)} speed: ORB vs cv::ORB",
                        [os.path.join(TOOLS, "orb_benchmark"), dataset, "--frames", "300", "--cv-threads", "1",
                         "--match-count", "--json", os.path.join(d, "orb.json")], os.path.join(d, "orb.log"),
                        expected_s=15)
    stream = os.path.join(d, "stream.bin")
    common = ["--camera", camera, "--vocabulary", vocabulary]
    codes["record"] = _run(progress, f"{os.path.basename(dataset)} speed: record the KeyFrame stream",
                           [os.path.join(TOOLS, "keyframe_stream"), "record", "--dataset", dataset, "--out", stream]
                           + common, os.path.join(d, "record.log"), expected_s=seconds + 10)
    if codes["record"] == 0:
        limit = int(os.environ.get("SPEED_EDGE_KEYFRAMES", "150"))
        codes["replay"] = _run(progress, f"{os.path.basename(dataset)} speed: edge replay (1 core)",
                               [os.path.join(TOOLS, "keyframe_stream"), "replay", "--stream", stream, "--mode",
                                "sequential", "--cores", "1", "--json", os.path.join(d, "edge.json")] + common
                               + (["--max-keyframes", str(limit)] if limit > 0 else []),
                               os.path.join(d, "replay.log"), expected_s=150)
    return {"dataset": dataset, "dir": d, "exit_codes": codes, "tracking_runs": runs}


# ---------------------------------------------------------------- report



def _verdict(ok):
    return "not measured" if ok is None else ("**PASS**" if ok else "**MISS**")


def _fmt(v, spec=".1f"):
    return "n/a" if v is None else f"{v:{spec}}"


def _split_p99(run_dir):
    import numpy as np
    from . import pipeline_stats  # numpy: imported when the section is written
    t, ms = pipeline_stats.tracking_series(run_dir)
    if ms is None or not len(ms):
        return None, 0, None
    cpu = pipeline_stats.tracking_cpu_ms(run_dir)
    return float(np.percentile(ms, 99)), int(len(ms)), None if cpu is None else float(np.percentile(cpu, 99))


def speed_section(rep, section, out_dir, manifest):
    """Adds '## Speed' to `section` and the speed targets to `rep`; returns the figures."""
    import numpy as np
    figures = {}
    section.line("## Speed (issue 15)")
    section.line()
    entries = manifest.get("speed") or []
    if not entries:
        section.line("not measured (`make bench BENCH_ARGS=\"--only speed,monolithic,split\"`).")
        section.line()
    for entry in entries:
        name = os.path.basename(entry["dataset"].rstrip("/"))
        d = entry["dir"]
        fig = figures.setdefault(name, {})
        section.line(f"### {name}")
        section.line()

        # Tracking only: CPU of the tracking thread per frame, by stage, each run and their median.
        runs = [m for m in (_read(os.path.join(d, f"tracking_{k}", "metrics.json"))
                            for k in range(entry.get("tracking_runs", 0))) if m and m.get("tracking_cpu_ms")]
        rows = []
        for k, m in enumerate(runs):
            st = m.get("tracking_stage_cpu_ms", {})
            rows.append([f"run {k + 1}", _fmt(m["tracking_cpu_ms"]["median"]), _fmt(m["tracking_cpu_ms"]["p95"])]
                        + [f"{_fmt((st.get(s) or {}).get('median'), '.2f')} / {_fmt((st.get(s) or {}).get('p95'), '.2f')}"
                           for s in STAGES] + [_fmt((m.get("ate_rmse_m") or 0) * 100, ".2f")])
        med = p95 = None
        if runs:
            med = float(np.median([m["tracking_cpu_ms"]["median"] for m in runs]))
            p95 = float(np.median([m["tracking_cpu_ms"]["p95"] for m in runs]))
            worst = max(m["tracking_cpu_ms"]["p95"] for m in runs)
            fig["tracking_cpu_ms"] = {"median": med, "p95": p95, "worst_p95": worst, "runs": len(runs),
                                      "per_run": [m["tracking_cpu_ms"] for m in runs],
                                      "stages": [m.get("tracking_stage_cpu_ms") for m in runs]}
            section.line(f"Tracking only (`edge_slam_run --no-mapping --pace none`, {len(runs)} runs): CPU time of the "
                         "tracking thread per frame, whole and per stage (median / p95 ms; the stages are exclusive "
                         "and add up to the frame).")
            section.line()
            section.table(["run", "frame median", "frame p95"] + STAGES + ["ATE [cm]"], rows)
        else:
            section.line("Tracking only: not measured.")
            section.line()
        ok_med = None if med is None else med <= TARGETS["tracking_cpu_median_ms"]
        ok_p95 = None if p95 is None else p95 <= TARGETS["tracking_cpu_p95_ms"]
        rep.target(f"Tracking CPU per frame, tracking only, median <= 12 ms ({name})",
                   "n/a" if med is None else f"{med:.1f} ms (median of {len(runs)} runs)", ok_med)
        rep.target(f"Tracking CPU per frame, tracking only, p95 <= 18 ms ({name})",
                   "n/a" if p95 is None else f"{p95:.1f} ms (median of {len(runs)} runs, worst {worst:.1f})", ok_p95)

        # ORB extraction against cv::ORB at the same keypoint count, same process.
        orb = _read(os.path.join(d, "orb.json"))
        ok = None
        if orb:
            fig["orb"] = orb
            ok = orb["ratio_cpu"] <= TARGETS["orb_ratio"]
            o, c = orb["ours"], orb["opencv"]
            section.table(["extractor", "CPU mean [ms]", "CPU median [ms]", "keypoints", "fullest 4x4 cell / share",
                           "40 px cells occupied"],
                          [["ours (quadtree)", _fmt(o["cpu_mean_ms"], ".2f"), _fmt(o["cpu_median_ms"], ".2f"),
                            _fmt(o["keypoints_mean"], ".0f"), _fmt(o["fullest_4x4_over_share"], ".2f"),
                            f"{o['occupied_40px'] * 100:.0f}%"],
                           [f"cv::ORB (nfeatures {orb.get('opencv_nfeatures', 1000)})", _fmt(c["cpu_mean_ms"], ".2f"),
                            _fmt(c["cpu_median_ms"], ".2f"), _fmt(c["keypoints_mean"], ".0f"),
                            _fmt(c["fullest_4x4_over_share"], ".2f"), f"{c['occupied_40px'] * 100:.0f}%"]])
            figure = f"ours / cv::ORB CPU {orb['ratio_cpu']:.2f} ({o['keypoints_mean']:.0f} vs {c['keypoints_mean']:.0f} keypoints)"
        else:
            figure = "n/a"
        section.line(f"ORB extraction ({orb['frames'] if orb else 0} frames, 1 OpenCV thread, interleaved in one "
                     f"process): {figure} -> {_verdict(ok)}")
        section.line()
        rep.target(f"ORB extraction <= cv::ORB at the same keypoint count ({name})", figure, ok)

        # Local BA of the bench's monolithic run.
        mono = _read(os.path.join(out_dir, "runs", name, "monolithic", "metrics.json")) or {}
        ba = mono.get("local_ba_ms") or {}
        mapping = mono.get("local_mapping") or {}
        ok_ba = None
        if ba.get("count"):
            aborted = mapping.get("local_ba_aborted")
            ok_ba = ba["median"] <= TARGETS["local_ba_median_ms"] and ba["p95"] <= TARGETS["local_ba_p95_ms"] and \
                (aborted == 0)
            figure = (f"median {ba['median']:.0f} ms, p95 {ba['p95']:.0f} ms, max {ba['max']:.0f} ms, "
                      f"{ba['count']} runs, {aborted if aborted is not None else 'n/a'} aborted; "
                      f"ATE {_fmt((mono.get('ate_rmse_m') or 0) * 100, '.2f')} cm")
            fig["local_ba"] = {"ms": ba, "aborted": aborted, "ate_rmse_m": mono.get("ate_rmse_m")}
        else:
            figure = "n/a (no monolithic run)"
        section.line(f"Local BA (monolithic run of this bench, real-time playback): {figure} -> {_verdict(ok_ba)}")
        section.line()
        rep.target(f"Local BA median <= 60 ms, p95 <= 150 ms, none aborted ({name})", figure, ok_ba)

        # Edge throughput.
        edge = _read(os.path.join(d, "edge.json"))
        ok = None
        if edge:
            fig["edge"] = {k: edge.get(k) for k in ("mode", "cores", "records", "processed", "wall_s", "cpu_s",
                                                    "keyframes_per_s", "cpu_ms_per_keyframe")}
            ok = edge["keyframes_per_s"] >= TARGETS["edge_keyframes_per_s"]
            eba = edge.get("local_ba_ms") or {}
            figure = (f"{edge['keyframes_per_s']:.2f} KeyFrames/s ({edge['processed']} KeyFrames: the first "
                      f"{edge['records']} of the recorded stream; {edge['cpu_ms_per_keyframe']:.0f} ms CPU each, i.e. "
                      f"{1000.0 / max(edge['cpu_ms_per_keyframe'], 1e-9):.2f} per CPU-second; local BA median "
                      f"{_fmt(eba.get('median'), '.0f')} ms)")
        else:
            figure = "n/a"
        section.line(f"Edge: the KeyFrame records the mobile makes on this sequence, replayed into an EdgeSession on "
                     f"one core, each as soon as Local-Mapping finished the previous one (`keyframe_stream`): "
                     f"{figure} -> {_verdict(ok)}")
        section.line()
        rep.target(f"Edge KeyFrames/s through Local-Mapping, one core >= 5 ({name})", figure, ok)

        # Split mobile tracking wall p99.
        p99, n, cpu_p99 = _split_p99(os.path.join(out_dir, "runs", name, "split"))
        ok = None if p99 is None else p99 <= TARGETS["split_tracking_p99_ms"]
        figure = "n/a (no split run)" if p99 is None else f"p99 {p99:.1f} ms over {n} frames"
        if cpu_p99 is not None:
            # Both sides share this PC's 2 cores: the difference is the tracking thread waiting for one.
            figure += f" (CPU of the tracking thread: p99 {cpu_p99:.1f} ms)"
        if p99 is not None:
            fig["split_tracking_p99_ms"] = p99
        if cpu_p99 is not None:
            fig["split_tracking_cpu_p99_ms"] = cpu_p99
        section.line(f"Split mode, mobile tracking wall time per frame: {figure} -> {_verdict(ok)}")
        section.line()
        rep.target(f"Split mobile tracking wall p99 <= 30 ms ({name})", figure, ok)
    return figures
