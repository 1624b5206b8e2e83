#!/usr/bin/python3
"""One split run over a shaped link (paper Table 5): mobile and edge in two network namespaces.

python3 -m bench.netns_run --bag <bag> --up <Mbit/s> --down <Mbit/s> [--delay-ms 5] --out <dir>  (root)

Two namespaces joined by a veth pair (mobile 10.77.0.1, edge 10.77.0.2). Each end's egress is
shaped with tc: a token bucket (tbf) at the upload rate on the mobile side and the download
rate on the edge side, each followed by a netem delay. The ROS master and the edge nodelet
manager live in the edge namespace; the mobile nodelet manager, rosbag play (the robot's
camera) and a pose recorder in the mobile namespace, so every topic between them crosses the
shaped link. At the end both sides' counters are read over their services and written with the
mobile trajectory to <dir>: trajectory.txt, counters.json, log.txt. Everything (processes,
namespaces, veth) is removed on exit, also on failure or Ctrl-C.
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import time

from .final_trajectory import compose
from .netns import NamespacePair
from .ros_util import edge_settled_key, wait_until_steady

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
MOBILE_IP, EDGE_IP, PORT = "10.77.0.1", "10.77.0.2", 11311


def wait_until(condition, timeout, step=0.5):
    """condition()'s first true value within `timeout` s, else None."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(step)
    return None


def spawn(nets, side, cmd, log):
    return subprocess.Popen(nets.wrap(side, cmd), env=nets.ros_env(side, PORT), cwd=ROOT, stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bag", required=True)
    ap.add_argument("--up", type=float, required=True, help="upload (mobile -> edge) Mbit/s")
    ap.add_argument("--down", type=float, required=True, help="download (edge -> mobile) Mbit/s")
    ap.add_argument("--delay-ms", type=float, default=5.0)
    ap.add_argument("--camera", default=os.path.join(ROOT, "config/camera_synthetic.yaml"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--drain-timeout", type=float, default=60.0,
                    help="after the bag: at most this long for every KeyFrame to be durable and the edge to settle")
    args = ap.parse_args()
    if os.geteuid() != 0:
        sys.exit("netns_run: needs root (ip netns, tc)")
    os.makedirs(args.out, exist_ok=True)
    log = open(os.path.join(args.out, "log.txt"), "w")
    nets = NamespacePair("esb", os.getpid() % 100000, {"mobile": MOBILE_IP, "edge": EDGE_IP})
    procs = []

    def cleanup(*_):
        for p in reversed(procs):
            if p.poll() is None:
                try:
                    os.killpg(p.pid, signal.SIGINT)
                except ProcessLookupError:
                    pass
        deadline = time.monotonic() + 15
        for p in procs:
            try:
                p.wait(max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
        nets.destroy()

    signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
    counters = {"up_mbps": args.up, "down_mbps": args.down, "delay_ms": args.delay_ms}
    try:
        counters["delay_applied"] = nets.create({"mobile": args.up, "edge": args.down}, args.delay_ms)
        launch = os.path.join(ROOT, "launch")
        procs.append(spawn(nets, "edge", ["roscore", "-p", str(PORT)], log))
        for _ in range(100):
            if subprocess.run(nets.wrap("edge", ["rosparam", "set", "/use_sim_time", "true"]),
                              env=nets.ros_env("edge", PORT), capture_output=True).returncode == 0:
                break
            time.sleep(0.3)
        out = os.path.abspath(args.out)
        outputs = {"edge": {"stats_csv": "edge_stats.csv", "metrics_file": "edge_metrics.json",
                            "keyframes_file": "edge_keyframes.txt"},
                   "mobile": {"stats_csv": "mobile_stats.csv", "metrics_file": "mobile_metrics.json",
                              "trajectory_file": "trajectory_online.txt", "anchors_file": "mobile_anchors.txt"}}
        for side in ("edge", "mobile"):
            path = os.path.join(launch, f"{side}.launch")
            text = open(path).read()
            cmd = ["roslaunch", "--wait", path, f"camera_config:={args.camera}"]
            # The nodelets' own measurement files, for the launch arguments this version has.
            cmd += [f"{arg}:={os.path.join(out, name)}" for arg, name in outputs[side].items()
                    if f'name="{arg}"' in text]
            procs.append(spawn(nets, side, cmd, log))
        procs.append(spawn(nets, "mobile", [sys.executable, "-m", "bench.odometry_recorder",
                                            "--out", os.path.join(args.out, "trajectory.txt")], log))
        # Both nodelets have loaded the vocabulary once they offer their services.
        for name in ("/edge_slam/edge/status", "/edge_slam/mobile/delivery_status"):
            if not wait_until(lambda: nets.call_service("mobile", name, PORT), 120):
                raise RuntimeError(f"{name} never answered: see {args.out}/log.txt")
        t0 = time.time()
        play = spawn(nets, "mobile", ["rosbag", "play", "--clock", "--quiet", args.bag], log)
        procs.append(play)
        play.wait()
        counters["play_s"] = round(time.time() - t0, 1)
        # Every KeyFrame the mobile made acknowledged as durable (or received), then the edge settled.
        wait_until(lambda: (nets.call_service("mobile", "/edge_slam/mobile/delivery_status", PORT) or {})
                   .get("queued", 1) == 0, args.drain_timeout)
        wait_until_steady(lambda: edge_settled_key(nets.call_service("mobile", "/edge_slam/edge/status", PORT)), 4.0,
                          args.drain_timeout)
        counters["mobile"] = nets.call_service("mobile", "/edge_slam/mobile/map_update_status", PORT)
        counters["edge"] = nets.call_service("mobile", "/edge_slam/edge/status", PORT)
    finally:
        cleanup()
        json.dump(counters, open(os.path.join(args.out, "counters.json"), "w"), indent=2)
    # Final trajectory as in `make eval MODE=split` (frames re-anchored on the edge's final
    # KeyFrames) when both sides wrote their files; the recorded odometry otherwise.
    anchors, kfs = (os.path.join(args.out, f) for f in ("mobile_anchors.txt", "edge_keyframes.txt"))
    if os.path.isfile(anchors) and os.path.isfile(kfs):
        os.replace(os.path.join(args.out, "trajectory.txt"), os.path.join(args.out, "trajectory_odometry.txt"))
        try:
            compose(anchors, kfs, os.path.join(args.out, "trajectory.txt"))
            counters["trajectory"] = "final (compose_trajectory)"
        except RuntimeError as e:
            log.write(f"compose_trajectory: {e}\n")
            counters["trajectory"] = "none (compose_trajectory failed)"
    else:
        counters["trajectory"] = "tracking odometry"
    json.dump(counters, open(os.path.join(args.out, "counters.json"), "w"), indent=2)
    print(json.dumps(counters))


if __name__ == "__main__":
    main()
