"""Two network namespaces joined by a veth pair, for running mobile and edge as on two machines:
used by the bandwidth-limit benchmark (bench.netns_run) and the link-cut delivery test
(test/delivery/delivery_harness.py). Root only (ip netns, tc)."""
import os
import signal
import subprocess

from .ros_util import rosservice_call

SIDES = ("mobile", "edge")


class NetnsError(RuntimeError):
    """A namespace command failed: the message names it and its error output."""


def sh(*cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise NetnsError("network namespace setup failed: %s: %s" % (" ".join(cmd), r.stderr.strip()))


class NamespacePair:
    """Namespaces <prefix>_m<tag> / <prefix>_e<tag> with a veth pair between them, mobile at
    ips["mobile"], edge at ips["edge"] (/24). Use create() then destroy() (in a finally)."""

    def __init__(self, prefix, tag, ips):
        self.ns = {"mobile": f"{prefix}_m{tag}", "edge": f"{prefix}_e{tag}"}
        self.veth = {"mobile": f"{prefix}m{tag}", "edge": f"{prefix}e{tag}"}  # interface names: <= 15 chars
        self.ips = dict(ips)
        if any(len(v) > 15 for v in self.veth.values()):
            raise ValueError(f"veth names {self.veth} longer than 15 characters")

    @staticmethod
    def available():
        """(True, "") as root, else (False, why)."""
        if os.geteuid() != 0:
            return False, "needs root (ip netns, veth, tc)"
        return True, ""

    def create(self, rates_mbit=None, delay_ms=None):
        """Makes both namespaces and the link. rates_mbit: {"mobile": upload, "edge": download}
        shapes each end's egress with a token bucket, then delay_ms of netem delay. Returns whether
        the delay could be added (some kernels have no sch_netem)."""
        delay_ok = True
        for side in SIDES:
            sh("ip", "netns", "add", self.ns[side])
        sh("ip", "link", "add", self.veth["mobile"], "type", "veth", "peer", "name", self.veth["edge"])
        for side in SIDES:
            ns, dev = self.ns[side], self.veth[side]
            sh("ip", "link", "set", dev, "netns", ns)
            sh("ip", "-n", ns, "addr", "add", self.ips[side] + "/24", "dev", dev)
            sh("ip", "-n", ns, "link", "set", "lo", "up")
            sh("ip", "-n", ns, "link", "set", dev, "up")
            if rates_mbit:
                sh("ip", "netns", "exec", ns, "tc", "qdisc", "add", "dev", dev, "root", "handle", "1:", "tbf",
                   "rate", f"{rates_mbit[side]}mbit", "burst", "64kb", "latency", "400ms")
                if delay_ms:
                    try:
                        sh("ip", "netns", "exec", ns, "tc", "qdisc", "add", "dev", dev, "parent", "1:1", "handle",
                           "10:", "netem", "delay", f"{delay_ms:g}ms")
                    except NetnsError:
                        delay_ok = False
        return delay_ok

    def set_link(self, up):
        sh("ip", "-n", self.ns["mobile"], "link", "set", self.veth["mobile"], "up" if up else "down")

    def wrap(self, side, cmd):
        """The command run inside the namespace of `side`."""
        return ["ip", "netns", "exec", self.ns[side]] + list(cmd)

    def ros_env(self, side, master_port, base=None):
        """Environment of a ROS process on `side`: the master on the edge side."""
        ip = self.ips[side]
        return dict(base if base is not None else os.environ, ROS_MASTER_URI=f"http://{self.ips['edge']}:{master_port}",
                    ROS_IP=ip, ROS_HOSTNAME=ip)

    def call_service(self, side, name, master_port, timeout=30):
        """`rosservice call` from inside a namespace: the response as a dict, None on failure."""
        return rosservice_call(name, env=self.ros_env(side, master_port), prefix=self.wrap(side, []), timeout=timeout)

    def destroy(self):
        """Kills what still runs inside and deletes both namespaces (the veth pair goes with them)."""
        for side in SIDES:
            pids = subprocess.run(["ip", "netns", "pids", self.ns[side]], capture_output=True, text=True).stdout.split()
            for pid in pids:
                try:
                    os.kill(int(pid), signal.SIGKILL)
                except (ProcessLookupError, ValueError):
                    pass
            subprocess.run(["ip", "netns", "del", self.ns[side]], stderr=subprocess.DEVNULL)
