"""Scaling section of the benchmark (issue 16): one edge serving 1, 2 and 3 mobiles on the
embedded synthetic room, played at SCALING_RATE (default 0.5: three mobiles and the edge on a
2-core machine cannot hold real time). For each N the edge process's CPU % and RSS (psutil,
bench.proc_sampler) and, per mobile, the edge's update latency (build start -> published) and
the KeyFrame transmit latency (created on the mobile -> received on the edge), from the edge's
metrics.json; with N >= 2 the merges and the combined final ATE (bench.multi_eval).

  1 mobile:  `make eval MODE=split` (the edge in its one-robot mode)
  2 mobiles: `make eval MODE=multi` on bags/synthetic_room + bags/synthetic_room_robot2
  3 mobiles: the same plus a third robot replaying robot 1's walk (two robots on one bag: the
             issue's stress case; its map merges with robot 1's at once)

python3 -m bench.scaling --out DIR [--robots 1,2,3] [--rate 0.5]
(venv python). Writes DIR/<N>/ (each run's outputs and proc.csv), DIR/scaling.json and
DIR/scaling.png, and prints the table. run_scaling / scaling_section are what bench.py and
report.py call (variant "scaling"). Robot 2's data: `make dataset-multi`.
"""
import argparse
import json
import os
import subprocess
import sys

from .bench_data import read_json as _read

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
ROBOT1, ROBOT2 = "bags/synthetic_room", "bags/synthetic_room_robot2"


def edge_usage(proc_csv):
    """(CPU % over the run, peak RSS MB) of the edge from a proc_sampler file, or (None, None)."""
    rows = []
    try:
        with open(proc_csv) as f:
            next(f)
            for line in f:
                t, role, _pid, cpu, rss = line.strip().split(",")
                if role == "edge":
                    rows.append((float(t), float(cpu), int(rss)))
    except (OSError, StopIteration, ValueError):
        return None, None
    if len(rows) < 2 or rows[-1][0] <= rows[0][0]:
        return None, None
    cpu_percent = 100.0 * (rows[-1][1] - rows[0][1]) / (rows[-1][0] - rows[0][0])
    return cpu_percent, max(r[2] for r in rows) / 1024.0


def latencies(edge_metrics):
    """Per mobile: (update latency median, p95), (KeyFrame transmit median, p95), ms."""
    out = {}
    robots = (edge_metrics or {}).get("robots")
    if robots:
        for r, m in sorted(robots.items(), key=lambda kv: int(kv[0])):
            u, k = m.get("update_latency_ms") or {}, m.get("keyframe_transmit_ms") or {}
            out[f"robot{int(r) + 1}"] = {"update_ms": [u.get("median"), u.get("p95")],
                                         "keyframe_transmit_ms": [k.get("median"), k.get("p95")]}
    elif edge_metrics:
        u, k = edge_metrics.get("update_build_ms") or {}, edge_metrics.get("keyframe_transmit_ms") or {}
        out["robot1"] = {"update_ms": [u.get("median"), u.get("p95")],
                         "keyframe_transmit_ms": [k.get("median"), k.get("p95")]}
    return out


def run_one(n, out_dir, rate):
    """One run with n mobiles into out_dir/<n>; returns its figures."""
    d = os.path.join(out_dir, str(n))
    os.makedirs(d, exist_ok=True)
    env = dict(os.environ, OUT=d, PATH="/usr/bin:" + os.environ.get("PATH", ""))
    if n == 1:
        env.update(DATASET=ROBOT1, MODE="split", SPLIT_LAUNCH_ARGS=f"rate:={rate}")
    else:
        datasets = [ROBOT1, ROBOT2] + [ROBOT1] * (n - 2)
        env.update(DATASET=ROBOT1, MODE="multi", ROBOT_DATASETS=" ".join(datasets), MULTI_LAUNCH_ARGS=f"rate:={rate}")
    with open(os.path.join(d, "eval.log"), "w") as log:
        run = subprocess.Popen(["bash", "scripts/eval.sh"], cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT)
        sampler = subprocess.Popen([sys.executable, "-m", "bench.proc_sampler", "--root-pid", str(run.pid),
                                    "--out", os.path.join(d, "proc.csv"), "--hz", "4",
                                    "--role", "edge=__name:=edge_manager"], cwd=HERE + "/..")
        rc = run.wait()
        sampler.wait()
    cpu, rss = edge_usage(os.path.join(d, "proc.csv"))
    metrics = _read(os.path.join(d, "metrics.json")) or {}
    fig = {"mobiles": n, "rc": rc, "rate": rate, "edge_cpu_percent": cpu, "edge_rss_peak_mb": rss,
           "latency": latencies(_read(os.path.join(d, "edge_metrics.json"))),
           "ate_rmse_m": metrics.get("ate_rmse_m"), "merges": metrics.get("merges") if n > 1 else None}
    return fig


def run_scaling(out_dir, robots=(1, 2, 3), rate=0.5):
    if any(n > 1 for n in robots) and not os.path.isdir(os.path.join(ROOT, ROBOT2)):
        raise SystemExit(f"scaling: robot 2's data {ROBOT2} not found: run `make dataset-multi` first")
    figures = [run_one(n, out_dir, rate) for n in robots]
    with open(os.path.join(out_dir, "scaling.json"), "w") as f:
        json.dump(figures, f, indent=2)
    # No plot here: the bench runs under Debian's python3 (rospy), which has no matplotlib; the
    # report (venv python) draws it in scaling_section.
    return figures


def _fmt(v, spec=".1f"):
    return "-" if v is None else format(v, spec)


def table(figures):
    lines = ["| mobiles | edge CPU % | edge RSS peak MB | per mobile: update latency median / p95 ms | "
             "KeyFrame transmit median / p95 ms | merges | combined final ATE cm |",
             "|---|---|---|---|---|---|---|"]
    for f in figures:
        lat = f["latency"]
        upd = "; ".join(f"{r} {_fmt(v['update_ms'][0])} / {_fmt(v['update_ms'][1])}" for r, v in lat.items())
        kft = "; ".join(f"{r} {_fmt(v['keyframe_transmit_ms'][0])} / {_fmt(v['keyframe_transmit_ms'][1])}"
                        for r, v in lat.items())
        ate = None if f["ate_rmse_m"] is None else f["ate_rmse_m"] * 100
        lines.append(f"| {f['mobiles']} | {_fmt(f['edge_cpu_percent'])} | {_fmt(f['edge_rss_peak_mb'], '.0f')} | "
                     f"{upd or '-'} | {kft or '-'} | {_fmt(f['merges'], 'd') if f['merges'] is not None else '-'} | "
                     f"{_fmt(ate, '.2f')} |")
    return lines


def plot(figures, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = [f["mobiles"] for f in figures]
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    ax[0].plot(n, [f["edge_cpu_percent"] or 0 for f in figures], "o-")
    ax[0].set(title="edge CPU", xlabel="mobiles", ylabel="% of one core")
    ax[1].plot(n, [f["edge_rss_peak_mb"] or 0 for f in figures], "o-")
    ax[1].set(title="edge RSS peak", xlabel="mobiles", ylabel="MB")
    for key, style in (("update_ms", "o-"), ("keyframe_transmit_ms", "s--")):
        med = [max([v[key][0] or 0 for v in f["latency"].values()] or [0]) for f in figures]
        ax[2].plot(n, med, style, label=key.replace("_ms", "") + " (worst mobile's median)")
    ax[2].set(title="latency", xlabel="mobiles", ylabel="ms")
    ax[2].legend(fontsize=8)
    for a in ax:
        a.set_xticks(n)
        a.set_ylim(bottom=0)  # from zero: the growth is read against the whole
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def scaling_section(section, out_dir, manifest):
    """Adds '## Scaling' (issue 16) to a report section; returns the figures."""
    figures = _read(os.path.join(out_dir, "scaling", "scaling.json")) if "scaling" in manifest else None
    section.line("## Scaling: one edge, several mobiles (issue 16)")
    section.line()
    if not figures:
        section.line("not measured (`make dataset-multi`, then `make bench BENCH_ARGS=\"--only scaling\"`).")
        section.line()
        return None
    section.line(f"Synthetic room played at rate {figures[0]['rate']} (3 mobiles and the edge do not hold real "
                 "time on 2 cores); 1 mobile = `MODE=split`, 3 = robot 1, robot 2 and robot 1's walk again.")
    section.line()
    for line in table(figures):
        section.line(line)
    section.line()
    plot(figures, os.path.join(out_dir, "scaling", "scaling.png"))
    section.line("![scaling](scaling/scaling.png)")
    section.line()
    return figures


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--robots", default="1,2,3", help="comma-separated mobile counts (1..4)")
    ap.add_argument("--rate", type=float, default=float(os.environ.get("SCALING_RATE", "0.5")))
    a = ap.parse_args()
    robots = [int(x) for x in a.robots.split(",") if x]
    if not robots or any(n < 1 or n > 4 for n in robots):
        ap.error("--robots: counts between 1 and 4")
    if not 0.05 <= a.rate <= 2.0:
        ap.error("--rate: between 0.05 and 2")
    os.makedirs(a.out, exist_ok=True)
    figures = run_scaling(os.path.abspath(a.out), robots, a.rate)
    print("\n".join(table(figures)))


if __name__ == "__main__":
    main()
