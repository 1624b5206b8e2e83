#!/usr/bin/python3
"""CPU and memory of named processes from /proc, sampled at a fixed rate (benchmark suite).

proc_sampler.py --root-pid PID --out samples.csv [--hz 20] --role mobile=edge_slam_run [--role edge=...]

Only descendants of --root-pid are considered (other people's runs on the same machine never
match), and a role is the first descendant whose command line contains the given text (e.g.
"__name:=mobile_manager" for the mobile nodelet manager). Each row: wall time, role, pid,
cumulative CPU seconds (utime + stime, all threads) and VmRSS in kB; CPU % is derived later
from the deltas, so a late start or a missed tick loses no CPU time. Stops when the root exits.
"""
import argparse
import os
import time

CLK_TCK = os.sysconf("SC_CLK_TCK")


def parent_map():
    """pid -> parent pid of every process now (unreadable entries skipped)."""
    parents = {}
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        # The command name (field 2) may hold spaces or ')': fields start after the last ')'.
        parents[int(name)] = int(stat.rsplit(")", 1)[1].split()[1])
    return parents


def descendants(root, parents):
    children = {}
    for pid, ppid in parents.items():
        children.setdefault(ppid, []).append(pid)
    found, stack = [], [root]
    while stack:
        for child in children.get(stack.pop(), []):
            found.append(child)
            stack.append(child)
    return found


def cmdline(pid):
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            return f.read().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def sample(pid):
    """(cpu seconds, rss kB) or None once the process is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        rss_kb = None
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    rss_kb = int(line.split()[1])
                    break
    except (OSError, IndexError, ValueError):
        return None
    if rss_kb is None:  # a zombie (exited, not yet reaped) has no VmRSS: it is gone
        return None
    # After ')': field 3 (state) is index 0, so utime (14) and stime (15) are indices 11 and 12.
    return (int(fields[11]) + int(fields[12])) / CLK_TCK, rss_kb


def alive(pid):
    """Running (a zombie, exited but not yet reaped by its parent, counts as gone)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root-pid", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--hz", type=float, default=20.0)
    ap.add_argument("--role", action="append", default=[], help="name=command-line text")
    args = ap.parse_args()
    roles = dict(r.split("=", 1) for r in args.role)
    me = os.getpid()
    found = {}  # role -> pid, kept once matched (a restarted process would be a new pid: re-matched)
    period = 1.0 / args.hz
    next_scan = 0.0
    with open(args.out, "w") as out:
        out.write("t,role,pid,cpu_s,rss_kb\n")
        tick = time.monotonic()
        while alive(args.root_pid):
            now = time.monotonic()
            if now >= next_scan and len(found) < len(roles):  # look for roles not seen yet, twice a second
                next_scan = now + 0.5
                for pid in descendants(args.root_pid, parent_map()):
                    if pid == me:
                        continue
                    text = cmdline(pid)
                    for role, needle in roles.items():
                        if role not in found and needle in text:
                            found[role] = pid
            wall = time.time()
            for role, pid in list(found.items()):
                s = sample(pid)
                if s is None:
                    del found[role]
                    continue
                out.write(f"{wall:.3f},{role},{pid},{s[0]:.2f},{s[1]}\n")
            out.flush()
            tick += period
            time.sleep(max(0.0, tick - time.monotonic()))


if __name__ == "__main__":
    main()
