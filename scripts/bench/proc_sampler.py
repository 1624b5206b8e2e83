"""CPU and memory of named processes, sampled with psutil at a fixed rate (benchmark suite).

python3 -m bench.proc_sampler --root-pid PID --out samples.csv [--hz 20] --role mobile=edge_slam_run [--role edge=...]

Only descendants of --root-pid are considered (other people's runs on the same machine never
match), and a role is the first descendant whose command line contains the given text (e.g.
"__name:=mobile_manager" for the mobile nodelet manager). Each row: wall time, role, pid,
cumulative CPU seconds (user + system, all threads) and resident memory in kB; CPU % is derived
later from the deltas, so a late start or a missed tick loses no CPU time. Stops when the root exits.
"""
import argparse
import os
import time

import psutil


def find_role(root, needle, exclude):
    """The first descendant of `root` whose command line contains `needle`, or None."""
    for child in root.children(recursive=True):
        if child.pid in exclude:
            continue
        try:
            if needle in " ".join(child.cmdline()):
                return child
        except (psutil.NoSuchProcess, psutil.AccessDenied, psutil.ZombieProcess):
            continue
    return None


def sample(proc):
    """(cpu seconds, rss kB) or None once the process is gone (or a zombie)."""
    try:
        with proc.oneshot():
            if proc.status() == psutil.STATUS_ZOMBIE:
                return None
            cpu = proc.cpu_times()
            return cpu.user + cpu.system, proc.memory_info().rss // 1024
    except (psutil.NoSuchProcess, psutil.AccessDenied, psutil.ZombieProcess):
        return None


def alive(proc):
    """Running (a zombie, exited but not yet reaped by its parent, counts as gone)."""
    try:
        return proc.status() != psutil.STATUS_ZOMBIE
    except (psutil.NoSuchProcess, psutil.ZombieProcess):
        return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root-pid", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--hz", type=float, default=20.0)
    ap.add_argument("--role", action="append", default=[], help="name=command-line text")
    args = ap.parse_args()
    roles = dict(r.split("=", 1) for r in args.role)
    try:
        root = psutil.Process(args.root_pid)
    except psutil.NoSuchProcess:
        root = None
    me = {os.getpid()}
    found = {}  # role -> psutil.Process, kept once matched (a restarted process is a new one: re-matched)
    period = 1.0 / args.hz
    next_scan = 0.0
    with open(args.out, "w") as out:
        out.write("t,role,pid,cpu_s,rss_kb\n")
        tick = time.monotonic()
        while root is not None and alive(root):
            now = time.monotonic()
            if now >= next_scan and len(found) < len(roles):  # look for roles not seen yet, twice a second
                next_scan = now + 0.5
                for role, needle in roles.items():
                    if role not in found:
                        proc = find_role(root, needle, me)
                        if proc is not None:
                            found[role] = proc
            wall = time.time()
            for role, proc in list(found.items()):
                s = sample(proc)
                if s is None:
                    del found[role]
                    continue
                out.write(f"{wall:.3f},{role},{proc.pid},{s[0]:.2f},{s[1]}\n")
            out.flush()
            tick += period
            time.sleep(max(0.0, tick - time.monotonic()))


if __name__ == "__main__":
    main()
