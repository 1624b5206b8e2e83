#!/usr/bin/python3
"""One split run over a shaped link (paper Table 5): mobile and edge in two network namespaces.

netns_run.py --bag <bag> --up <Mbit/s> --down <Mbit/s> [--delay-ms 5] --out <dir>  (root)

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

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))
MOBILE_IP, EDGE_IP, PORT = "10.77.0.1", "10.77.0.2", 11311


def sh(*cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


class Namespaces:
    def __init__(self, tag):
        self.mobile, self.edge = f"esb_m{tag}", f"esb_e{tag}"
        self.veth_m, self.veth_e = f"esbm{tag}", f"esbe{tag}"  # interface names: <= 15 chars

    def create(self, up, down, delay_ms):
        """Returns whether the delay could be added (netem is missing from some kernels)."""
        delay_ok = True
        for ns in (self.mobile, self.edge):
            sh("ip", "netns", "add", ns)
        sh("ip", "link", "add", self.veth_m, "type", "veth", "peer", "name", self.veth_e)
        for ns, dev, ip, rate in ((self.mobile, self.veth_m, MOBILE_IP, up), (self.edge, self.veth_e, EDGE_IP, down)):
            sh("ip", "link", "set", dev, "netns", ns)
            sh("ip", "-n", ns, "addr", "add", f"{ip}/24", "dev", dev)
            sh("ip", "-n", ns, "link", "set", "lo", "up")
            sh("ip", "-n", ns, "link", "set", dev, "up")
            # Egress of each end: token bucket at the link rate, then the one-way delay.
            sh("ip", "netns", "exec", ns, "tc", "qdisc", "add", "dev", dev, "root", "handle", "1:", "tbf",
               "rate", f"{rate}mbit", "burst", "64kb", "latency", "400ms")
            try:
                sh("ip", "netns", "exec", ns, "tc", "qdisc", "add", "dev", dev, "parent", "1:1", "handle", "10:",
                   "netem", "delay", f"{delay_ms:g}ms")
            except subprocess.CalledProcessError:
                delay_ok = False
        return delay_ok

    def destroy(self):
        for ns in (self.mobile, self.edge):
            pids = subprocess.run(["ip", "netns", "pids", ns], capture_output=True, text=True).stdout.split()
            for pid in pids:
                try:
                    os.kill(int(pid), signal.SIGKILL)
                except (ProcessLookupError, ValueError):
                    pass
            subprocess.run(["ip", "netns", "del", ns], stderr=subprocess.DEVNULL)


def ros_env(ip):
    return dict(os.environ, ROS_MASTER_URI=f"http://{EDGE_IP}:{PORT}", ROS_IP=ip, ROS_HOSTNAME=ip)


def spawn(ns, ip, cmd, log):
    return subprocess.Popen(["ip", "netns", "exec", ns] + cmd, env=ros_env(ip), cwd=ROOT, stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True)


def call_service(ns, ip, name, srv_type):
    """`rosservice call` from inside a namespace; the YAML answer as a dict (None on failure)."""
    r = subprocess.run(["ip", "netns", "exec", ns, "rosservice", "call", name], env=ros_env(ip),
                       capture_output=True, text=True, timeout=30)
    if r.returncode != 0:
        return None
    out = {}
    for line in r.stdout.splitlines():
        if ":" in line and not line.startswith(" "):
            k, v = line.split(":", 1)
            out[k.strip()] = v.strip()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bag", required=True)
    ap.add_argument("--up", type=float, required=True, help="upload (mobile -> edge) Mbit/s")
    ap.add_argument("--down", type=float, required=True, help="download (edge -> mobile) Mbit/s")
    ap.add_argument("--delay-ms", type=float, default=5.0)
    ap.add_argument("--camera", default=os.path.join(ROOT, "config/camera_synthetic.yaml"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--drain-s", type=float, default=10.0, help="wait after the bag ends before reading counters")
    args = ap.parse_args()
    if os.geteuid() != 0:
        sys.exit("netns_run: needs root (ip netns, tc)")
    os.makedirs(args.out, exist_ok=True)
    log = open(os.path.join(args.out, "log.txt"), "w")
    nets = Namespaces(os.getpid() % 100000)
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
        counters["delay_applied"] = nets.create(args.up, args.down, args.delay_ms)
        launch = os.path.join(ROOT, "launch")
        procs.append(spawn(nets.edge, EDGE_IP, ["roscore", "-p", str(PORT)], log))
        for _ in range(100):
            if subprocess.run(["ip", "netns", "exec", nets.edge, "rosparam", "set", "/use_sim_time", "true"],
                              env=ros_env(EDGE_IP), capture_output=True).returncode == 0:
                break
            time.sleep(0.3)
        out = os.path.abspath(args.out)
        outputs = {"edge": {"stats_csv": "edge_stats.csv", "metrics_file": "edge_metrics.json",
                            "keyframes_file": "edge_keyframes.txt"},
                   "mobile": {"stats_csv": "mobile_stats.csv", "metrics_file": "mobile_metrics.json",
                              "trajectory_file": "trajectory_online.txt", "anchors_file": "mobile_anchors.txt"}}
        for side, ns, ip in (("edge", nets.edge, EDGE_IP), ("mobile", nets.mobile, MOBILE_IP)):
            path = os.path.join(launch, f"{side}.launch")
            text = open(path).read()
            cmd = ["roslaunch", "--wait", path, f"camera_config:={args.camera}"]
            # The nodelets' own measurement files, for the launch arguments this version has.
            cmd += [f"{arg}:={os.path.join(out, name)}" for arg, name in outputs[side].items()
                    if f'name="{arg}"' in text]
            procs.append(spawn(ns, ip, cmd, log))
        procs.append(spawn(nets.mobile, MOBILE_IP, [sys.executable, os.path.join(HERE, "odometry_recorder.py"),
                                                    "--out", os.path.join(args.out, "trajectory.txt")], log))
        time.sleep(8)  # both nodelets load the vocabulary before the first frame
        t0 = time.time()
        play = spawn(nets.mobile, MOBILE_IP, ["rosbag", "play", "--clock", "--quiet", args.bag], log)
        procs.append(play)
        play.wait()
        counters["play_s"] = round(time.time() - t0, 1)
        time.sleep(args.drain_s)
        counters["mobile"] = call_service(nets.mobile, MOBILE_IP, "/edge_slam/mobile/map_update_status", None)
        counters["edge"] = call_service(nets.mobile, MOBILE_IP, "/edge_slam/edge/status", None)
    finally:
        cleanup()
        json.dump(counters, open(os.path.join(args.out, "counters.json"), "w"), indent=2)
    # Final trajectory as in `make eval MODE=split` (frames re-anchored on the edge's final
    # KeyFrames) when both sides wrote their files; the recorded odometry otherwise.
    anchors, kfs = (os.path.join(args.out, f) for f in ("mobile_anchors.txt", "edge_keyframes.txt"))
    tool = os.path.join(ROOT, "scripts", "split_trajectory.py")
    if os.path.isfile(tool) and os.path.isfile(anchors) and os.path.isfile(kfs):
        os.replace(os.path.join(args.out, "trajectory.txt"), os.path.join(args.out, "trajectory_odometry.txt"))
        made = subprocess.run([sys.executable, tool, anchors, kfs, os.path.join(args.out, "trajectory.txt")],
                              stdout=log, stderr=subprocess.STDOUT).returncode == 0
        counters["trajectory"] = "final (split_trajectory.py)" if made else "none (split_trajectory.py failed)"
    else:
        counters["trajectory"] = "tracking odometry"
    json.dump(counters, open(os.path.join(args.out, "counters.json"), "w"), indent=2)
    print(json.dumps(counters))


if __name__ == "__main__":
    main()
