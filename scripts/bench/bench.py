#!/usr/bin/python3
"""Benchmark suite orchestrator: `make bench DATASET=<TUM folder or bag> OUT=<dir>`.

Runs, on each dataset and in one go so that ratios compare like with like:
  monolithic       scripts/eval.sh MODE=monolithic (edge_slam_run: one process, 3 threads)
  split            scripts/eval.sh MODE=split (mobile + edge nodelet managers, rosbag play)
  split_controller split with the map-update controller disabling updates around the
                   sequence's fastest turn (found in its ground truth; planner_example)
  *_blank          both modes on a copy with 1 s of black colour frames (relocalization)
  robustness       N pairs (--robust-runs, default 5) of monolithic then split, back to back:
                   the spread of the final and online ATE (issue #13)
  speed            issue 15's speed figures (speed.py): tracking-only CPU per stage, ORB vs
                   cv::ORB, the edge's KeyFrames/s on a recorded stream (local BA and split p99
                   are read from the monolithic and split runs)
  scaling          issue 16 (scaling.py, once, not per dataset): one edge with 1, 2 and 3
                   mobiles on the synthetic room at half speed: edge CPU and RSS, each mobile's
                   update and KeyFrame latencies (robot 2's data: `make dataset-multi`)
and once the wire micro-benchmark (wire_benchmark: KeyFrame / update size, (de)serialization,
Local-Map rebuild). Each run gets a /proc CPU+RSS sampler (20 Hz) on the mobile and edge
processes and, in split mode, a topic-size recorder. Then report.py (venv: evo, matplotlib)
turns OUT/runs/ into OUT/report.md, OUT/bench.json and PNGs.

python3 -m bench.bench --out <dir> [--dataset D ...] [--only monolithic,split,...] [--report-only]
(from scripts/, or scripts/bench/bench.sh: `make bench`)
Every run's console output goes to OUT/runs/<dataset>/<variant>/log.txt; the terminal shows
one progress line (phase k/N, what runs, seconds elapsed / expected).
"""
import argparse
import json
import os
import platform
import signal
import socket
import subprocess
import sys
import time

from edge_slam_common.tum import list_seconds

from . import scaling, speed
from .fast_turn import fast_turn
from .ros_util import wait_for_service

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
SCRIPTS = os.path.dirname(HERE)

DEFAULT_DATASETS = ["bags/synthetic_room", "../shared/datasets/tum_fr1_rpy"]
VARIANTS = ["monolithic", "split", "split_controller", "monolithic_blank", "split_blank", "robustness", "bandwidth",
            "long", "speed", "scaling"]
ROBUST_RUNS = 5
# The long run: the embedded sequence's closed path driven 20 times at 15 fps (10 minutes),
# made by loop_sequence.py in OUT/data (text files and symlinks, no rendering); the split plays
# it live from the folder (tum_player), since a 10-minute bag of raw images would be ~14 GB.
LONG_SOURCE, LONG_LAPS, LONG_EVERY = "bags/synthetic_room", 20, 2
# Paper Table 5: upload / download Mbit/s, plus 5 ms one-way delay.
BANDWIDTH_LEVELS = {"high": (51, 67), "medium": (20, 20), "low": (15, 10)}
SAMPLER_ROLES = {"monolithic": ["mobile=edge_slam_run"],
                 "split": ["mobile=__name:=mobile_manager", "edge=__name:=edge_manager"]}
MOBILE_NS = "/edge_slam/mobile"
RUNNING = []  # process groups of the phase in progress: stopped on Ctrl-C (they run in their own sessions)


class Progress:
    """One terminal line, rewritten in place: which phase runs and how far it is."""

    def __init__(self, total):
        self.total, self.index, self.tty = total, 0, sys.stderr.isatty()

    def start(self, label):
        self.index += 1
        self.label, self.t0 = label, time.monotonic()
        self.show("")

    def show(self, detail):
        line = f"[bench {self.index}/{self.total}] {self.label} {detail}"
        if self.tty:
            sys.stderr.write("\r\033[K" + line)
        else:
            now = time.monotonic()  # logs: one line every 15 s is enough
            if detail == "" or now - getattr(self, "last", 0) >= 15:
                sys.stderr.write(line + "\n")
                self.last = now
        sys.stderr.flush()

    def done(self, result):
        self.last = 0  # the outcome line is always printed
        self.show(f"{result} ({time.monotonic() - self.t0:.0f} s)")
        if self.tty:
            sys.stderr.write("\n")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def sequence_seconds(folder):
    stamps = list_seconds(os.path.join(folder, "rgb.txt"))
    return stamps[-1] - stamps[0]


def robust_variants(runs):
    """The robustness runs in the order they run: each monolithic run right before its split."""
    return [f"robust_{mode}_{k}" for k in range(1, runs + 1) for mode in ("monolithic", "split")]


def default_datasets():
    """DEFAULT_DATASETS that exist, relative to this checkout or, in a git worktree, to the main
    checkout (../shared is next to the main clone, not next to the worktree)."""
    common = subprocess.run(["git", "rev-parse", "--path-format=absolute", "--git-common-dir"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    bases = [ROOT] + ([os.path.dirname(common)] if common.endswith("/.git") else [])
    found = []
    for d in DEFAULT_DATASETS:
        path = next((os.path.join(b, d) for b in bases if os.path.isdir(os.path.join(b, d))), None)
        if path:
            found.append(resolve_dataset(path))
    return found


def resolve_dataset(path):
    """A TUM folder; a bag is accepted when the TUM folder it was made from sits next to it."""
    path = os.path.abspath(os.path.join(ROOT, path))
    if path.endswith(".bag"):
        folder = path[:-4]
        if not os.path.isfile(os.path.join(folder, "rgb.txt")):
            sys.exit(f"bench: {path}: the benchmark needs the TUM folder the bag was made from ({folder}): "
                     "ground truth and the monolithic runner read it")
        path = folder
    if not os.path.isfile(os.path.join(path, "rgb.txt")):
        sys.exit(f"bench: {path} is not a TUM folder (no rgb.txt)")
    return path


def run_variant(progress, out_dir, dataset, variant, blank_dir, turn, expected_s):
    mode = "split" if "split" in variant else "monolithic"
    run_dir = os.path.join(out_dir, "runs", os.path.basename(dataset), variant)
    os.makedirs(run_dir, exist_ok=True)
    data = blank_dir if variant.endswith("_blank") else dataset
    env = dict(os.environ, DATASET=data, MODE=mode, OUT=run_dir)  # eval.sh picks the fr1 calibration itself
    if variant.startswith("long_"):
        env["SPLIT_SOURCE"] = "folder"  # no bag of a 10-minute sequence: tum_player reads the folder
        env["SPLIT_IMAGE_QUEUE"] = "2"  # a live camera: frames queued in the mobile would count in its RSS
        # the looped embedded sequence: its own vocabulary, not one trained on the copy
        env["EDGE_SLAM_ARGS"] = (env.get("EDGE_SLAM_ARGS", "") + " --vocabulary bags/vocabulary_synthetic.bin").strip()
    log = open(os.path.join(run_dir, "log.txt"), "w")
    progress.start(f"{os.path.basename(dataset)} {variant}:")
    t0 = time.time()
    proc = subprocess.Popen(["bash", "scripts/eval.sh"], cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)
    RUNNING[:] = [proc]
    helpers = [subprocess.Popen(
        [sys.executable, "-m", "bench.proc_sampler", "--root-pid", str(proc.pid),
         "--out", os.path.join(run_dir, "proc.csv"), "--hz", "20"]
        + [a for r in SAMPLER_ROLES[mode] for a in ("--role", r)], stdout=log, stderr=subprocess.STDOUT)]
    if mode == "split":
        helpers.append(subprocess.Popen([sys.executable, "-m", "bench.net_recorder",
                                         "--out", os.path.join(run_dir, "net.csv")],
                                        stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
    RUNNING.extend(helpers)
    if variant == "split_controller":
        if wait_for_service(MOBILE_NS + "/set_map_updates", 120, lambda: proc.poll() is None):
            windows = f"[[{turn[0]:.3f},{turn[1]:.3f}]]"
            helpers.append(subprocess.Popen(
                ["rosrun", "edge_slam_mobile", "planner_example", f"_turn_windows:={windows}",
                 f"_mobile_ns:={MOBILE_NS}", "_lead_time:=1.0", "_trail_time:=0.5"],
                stdout=log, stderr=subprocess.STDOUT, start_new_session=True))
        else:
            log.write("bench: the mobile's set_map_updates service never appeared: no controller\n")
    limit = 3 * expected_s + 180
    while proc.poll() is None:
        elapsed = time.time() - t0
        progress.show(f"{elapsed:4.0f} s / ~{expected_s:.0f} s")
        if elapsed > limit:
            log.write(f"bench: run exceeded {limit:.0f} s, stopped\n")
            os.killpg(proc.pid, signal.SIGINT)
            try:
                proc.wait(20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
            break
        time.sleep(1.0)
    rc = proc.wait()
    for h in helpers[1:]:  # recorder and controller: the sampler ends with the run by itself
        if h.poll() is None:
            os.killpg(h.pid, signal.SIGINT)
    for h in helpers:
        try:
            h.wait(15)
        except subprocess.TimeoutExpired:
            h.kill()
    info = {"dataset": dataset, "data": data, "variant": variant, "mode": mode, "exit_code": rc,
            "wall_s": round(time.time() - t0, 1), "expected_s": expected_s}
    if variant == "split_controller":
        info["controller_window"] = turn[:2]
    json.dump(info, open(os.path.join(run_dir, "run.json"), "w"), indent=2)
    progress.done("ok" if rc == 0 else f"FAILED (exit {rc}, see {os.path.relpath(run_dir, ROOT)}/log.txt)")
    return info


def run_bandwidth_levels(progress, out_dir, dataset, bag):
    """Split over a shaped veth link in two network namespaces, one run per level (root only)."""
    results = []
    for level, (up, down) in BANDWIDTH_LEVELS.items():
        run_dir = os.path.join(out_dir, "runs", os.path.basename(dataset), f"bandwidth_{level}")
        os.makedirs(run_dir, exist_ok=True)
        progress.start(f"{os.path.basename(dataset)} bandwidth {level} (up {up} / down {down} Mbit/s):")
        t0 = time.time()
        with open(os.path.join(run_dir, "runner.txt"), "w") as log:
            proc = subprocess.Popen([sys.executable, "-m", "bench.netns_run", "--bag", bag,
                                     "--up", str(up), "--down", str(down), "--out", run_dir],
                                    cwd=ROOT, stdout=log, stderr=subprocess.STDOUT)
            expected = sequence_seconds(dataset) + 25
            while proc.poll() is None:
                progress.show(f"{time.time() - t0:4.0f} s / ~{expected:.0f} s")
                if time.time() - t0 > 3 * expected + 120:
                    proc.terminate()  # netns_run cleans up its namespaces on SIGTERM
                time.sleep(1.0)
        results.append({"level": level, "up_mbps": up, "down_mbps": down, "exit_code": proc.returncode,
                        "wall_s": round(time.time() - t0, 1)})
        progress.done("ok" if proc.returncode == 0 else f"FAILED (exit {proc.returncode}, see runner.txt)")
    return results


def run_wire_benchmark(progress, out_dir, dataset):
    progress.start(f"wire micro-benchmark ({os.path.basename(dataset)}, 300 frames):")
    path = os.path.join(out_dir, "wire.json")
    tool = os.path.join(ROOT, ".ws/devel/lib/edge_slam_common/wire_benchmark")
    with open(os.path.join(out_dir, "wire_log.txt"), "w") as log:
        proc = subprocess.Popen([tool, "--dataset", dataset, "--frames", "300", "--out", path], cwd=ROOT,
                                stdout=log, stderr=subprocess.STDOUT)
        t0 = time.time()
        while proc.poll() is None:
            progress.show(f"{time.time() - t0:4.0f} s / ~60 s")
            time.sleep(1.0)
    progress.done("ok" if proc.returncode == 0 else f"FAILED (exit {proc.returncode}, see wire_log.txt)")


def read_manifest(out_dir):
    try:
        return json.load(open(os.path.join(out_dir, "manifest.json")))
    except (OSError, ValueError):
        return None


def save_manifest(out_dir, manifest, previous):
    """Writes the manifest; with --add, merged into the previous one: a dataset run again gets
    its variants replaced one by one, everything else of the earlier bench stays."""
    merged = manifest
    if previous:
        merged = dict(previous)
        merged.setdefault("added", []).append({k: manifest[k] for k in ("machine", "bench_wall_s") if k in manifest})
        by_name = {d["name"]: d for d in previous.get("datasets", [])}
        for entry in manifest["datasets"]:
            old = by_name.get(entry["name"])
            if old is None:
                merged["datasets"].append(entry)
                continue
            runs = {r["variant"]: r for r in old.get("runs", [])}
            runs.update({r["variant"]: r for r in entry["runs"]})
            old.update({k: v for k, v in entry.items() if k != "runs"})
            old["runs"] = list(runs.values())
        for key in ("long_run", "long_run_skipped", "scaling", "scaling_skipped"):
            if key in manifest:
                merged[key] = manifest[key]
        if "speed" in manifest:  # a dataset measured again replaces its speed entry
            again = {e["dataset"] for e in manifest["speed"]}
            merged["speed"] = [e for e in previous.get("speed", []) if e["dataset"] not in again] + manifest["speed"]
    json.dump(merged, open(os.path.join(out_dir, "manifest.json"), "w"), indent=2)
    return merged


def machine_info():
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    import psutil
    mem_kb = psutil.virtual_memory().total // 1024
    git = lambda *a: subprocess.run(["git", *a], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    return {"date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "nproc": os.cpu_count(), "cpu_model": cpu,
            "ram_gib": round(mem_kb / 1048576, 1), "kernel": platform.release(),
            "commit": git("rev-parse", "HEAD"), "commit_subject": git("log", "-1", "--format=%s"),
            "dirty": bool(git("status", "--porcelain", "--untracked-files=no")),
            "load_average_at_start": os.getloadavg()}


def stop_running():
    for p in RUNNING:
        if p.poll() is None:
            try:
                os.killpg(p.pid, signal.SIGINT)
                p.wait(20)
            except (ProcessLookupError, subprocess.TimeoutExpired):
                os.killpg(p.pid, signal.SIGKILL)


def main():
    try:
        run()
    except KeyboardInterrupt:
        sys.stderr.write("\nbench: interrupted; stopping the running phase\n")
        stop_running()
        sys.exit(130)


def run():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--dataset", action="append", default=[])
    ap.add_argument("--only", default=",".join(VARIANTS),
                    help=f"comma-separated variants to run, of {','.join(VARIANTS)} (default: all)")
    ap.add_argument("--no-wire", action="store_true", help="skip the wire micro-benchmark")
    ap.add_argument("--report-only", action="store_true", help="rebuild report.md from OUT/runs only")
    ap.add_argument("--long-laps", type=int, default=LONG_LAPS,
                    help=f"laps of the embedded path in the long run (default {LONG_LAPS}: 10 minutes)")
    ap.add_argument("--long-modes", default="monolithic,split",
                    help="modes of the long run")
    ap.add_argument("--robust-runs", type=int, default=ROBUST_RUNS,
                    help=f"pairs (monolithic then split) of the robustness section (default {ROBUST_RUNS})")
    ap.add_argument("--add", action="store_true",
                    help="keep what OUT already holds and add these runs (e.g. --only long after a full bench)")
    args = ap.parse_args()
    out_dir = os.path.abspath(args.out)
    os.makedirs(out_dir, exist_ok=True)
    # The tools run as modules of this package (python3 -m bench.<tool>): scripts/ on the path.
    os.environ["PYTHONPATH"] = os.pathsep.join([SCRIPTS] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
                                                            if p])
    venv_python = os.path.join(ROOT, ".venv/bin/python")
    report = [venv_python, "-m", "bench.report", "--out", out_dir]
    if args.report_only:
        sys.exit(subprocess.call(report))

    datasets = [resolve_dataset(d) for d in args.dataset] if args.dataset else default_datasets()
    variants = [v for v in args.only.split(",") if v]
    unknown = set(variants) - set(VARIANTS)
    if unknown:
        sys.exit(f"bench: unknown variant(s) {sorted(unknown)}; known: {VARIANTS}")
    # A private ROS master port: other people's roscore on this machine must not see our runs.
    # eval_split.sh starts its master on EVAL_ROS_PORT; the recorder and controller follow it.
    port = free_port()
    os.environ["EVAL_ROS_PORT"] = str(port)
    os.environ["ROS_MASTER_URI"] = f"http://localhost:{port}"
    os.environ.setdefault("ROS_HOME", os.path.join(out_dir, "ros_home"))

    manifest = {"machine": machine_info(), "datasets": [], "ros_master_uri": os.environ["ROS_MASTER_URI"]}
    previous = read_manifest(out_dir) if args.add else None
    with_bag = sum(os.path.isfile(d.rstrip("/") + ".bag") for d in datasets) if os.geteuid() == 0 else 0
    if args.robust_runs < 1:
        sys.exit("bench: --robust-runs must be >= 1")
    progress = Progress(len(datasets) * (len([v for v in variants if v not in ("bandwidth", "long", "robustness",
                                                                              "speed", "scaling")])
                                         + (2 * args.robust_runs if "robustness" in variants else 0)
                                         + (speed.phases() if "speed" in variants else 0)
                                         + (1 if any("blank" in v for v in variants) else 0))
                        + (len(BANDWIDTH_LEVELS) * with_bag if "bandwidth" in variants else 0)
                        + (1 + len(args.long_modes.split(",")) if "long" in variants else 0)
                        + (1 if "scaling" in variants else 0)
                        + (0 if args.no_wire else 1) + 1)
    t_start = time.time()
    for dataset in datasets:
        name = os.path.basename(dataset)
        seconds = sequence_seconds(dataset)
        turn = fast_turn(os.path.join(dataset, "groundtruth.txt"))
        first = list_seconds(os.path.join(dataset, "rgb.txt"))[0]
        entry = {"path": dataset, "name": name, "seconds": seconds, "fast_turn": turn[:2],
                 "fast_turn_from_start": [turn[0] - first, turn[1] - first],
                 "fast_turn_peak_deg_s": turn[2], "runs": []}
        blank_dir = os.path.join(out_dir, "data", name + "_blank")
        if any(v.endswith("_blank") for v in variants):
            progress.start(f"{name}: blank-frame copy")
            made = subprocess.run([sys.executable, os.path.join(SCRIPTS, "blank_frames.py"), dataset, blank_dir,
                                   "--start-fraction", "0.4", "--seconds", "1.0", "--force", "--json"],
                                  capture_output=True, text=True)
            if made.returncode == 0:
                blank = json.loads(made.stdout)
                entry["blank_range"] = blank["stamps"]
                entry["blank"] = f"{blank['count']} blank frames {blank['stamps'][0]:.3f}-{blank['stamps'][1]:.3f}"
            else:
                entry["blank"] = made.stderr.strip()
            progress.done(entry["blank"])
        for variant in variants:
            if variant in ("long", "scaling"):
                continue  # once, after the datasets
            if variant == "robustness":
                entry["robust_runs"] = args.robust_runs
                for name in robust_variants(args.robust_runs):
                    extra = 45 if "split" in name else 25
                    entry["runs"].append(run_variant(progress, out_dir, dataset, name, blank_dir, turn, seconds + extra))
                continue
            if variant == "speed":
                manifest.setdefault("speed", []).append(speed.run_speed(progress, out_dir, dataset, seconds))
                continue
            if variant == "bandwidth":
                bag = dataset.rstrip("/") + ".bag"
                if os.geteuid() != 0 or not os.path.isfile(bag):
                    entry["bandwidth_skipped"] = "needs root" if os.geteuid() != 0 else f"no bag {bag}"
                else:
                    entry["bandwidth"] = run_bandwidth_levels(progress, out_dir, dataset, bag)
                continue
            expected = seconds + (45 if variant.startswith("split") else 25)
            entry["runs"].append(run_variant(progress, out_dir, dataset, variant, blank_dir, turn, expected))
        manifest["datasets"].append(entry)
        save_manifest(out_dir, manifest, previous)
    long_dir = os.path.join(out_dir, "data", os.path.basename(LONG_SOURCE) + "_long")
    if "long" in variants:
        progress.start("long sequence:")
        made = subprocess.run([sys.executable, "-m", "bench.loop_sequence", os.path.join(ROOT, LONG_SOURCE),
                               long_dir, "--laps", str(args.long_laps), "--every", str(LONG_EVERY)],
                              capture_output=True, text=True)
        progress.done(made.stdout.strip() or made.stderr.strip())
    if "long" in variants and os.path.isfile(os.path.join(long_dir, "rgb.txt")):
        seconds = sequence_seconds(long_dir)
        entry = {"path": long_dir, "name": os.path.basename(long_dir), "seconds": seconds, "runs": [],
                 "laps": args.long_laps}
        for variant in args.long_modes.split(","):
            entry["runs"].append(run_variant(progress, out_dir, long_dir, f"long_{variant}", None, None,
                                             seconds + 40))
        manifest["long_run"] = entry
    elif "long" in variants:
        manifest["long_run_skipped"] = f"{long_dir} could not be made from {LONG_SOURCE}"
    if "scaling" in variants:
        progress.start("scaling: 1, 2, 3 mobiles on one edge")
        scaling_dir = os.path.join(out_dir, "scaling")
        os.makedirs(scaling_dir, exist_ok=True)
        try:
            figures = scaling.run_scaling(scaling_dir)
            manifest["scaling"] = scaling_dir
            progress.done(f"{len(figures)} runs")
        except SystemExit as e:
            manifest["scaling_skipped"] = str(e)
            progress.done(str(e))
    if not args.no_wire:
        synthetic = os.path.join(ROOT, "bags/synthetic_room")
        run_wire_benchmark(progress, out_dir, synthetic if os.path.isdir(synthetic) else datasets[0])
    manifest["bench_wall_s"] = round(time.time() - t_start, 1)
    manifest = save_manifest(out_dir, manifest, previous)
    progress.start("report:")
    rc = subprocess.call(report)
    progress.done("ok" if rc == 0 else f"FAILED (exit {rc})")
    if rc == 0:
        print(f"bench: wrote {out_dir}/report.md and bench.json in {(time.time() - t_start) / 60:.1f} min")
    sys.exit(rc)


if __name__ == "__main__":
    main()
