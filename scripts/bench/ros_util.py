"""ROS helpers shared by the bench tools and test/delivery: one parser of `rosservice call`
output and rospy's own wait for a service."""
import subprocess
import sys
import time

import yaml


def parse_rosservice_output(text):
    """`rosservice call` prints the response as YAML: a dict of its fields (None when empty)."""
    doc = yaml.safe_load(text) if text.strip() else None
    return doc if isinstance(doc, dict) else None


def rosservice_call(name, env=None, prefix=(), timeout=30):
    """`[prefix...] rosservice call <name>` (prefix: e.g. `ip netns exec <ns>`), the response as a
    dict; None when the service is not there, the call fails or it takes longer than `timeout` s."""
    try:
        r = subprocess.run(list(prefix) + ["rosservice", "call", name], env=env, capture_output=True, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return None
    return parse_rosservice_output(r.stdout) if r.returncode == 0 else None


def wait_for_service(name, timeout, keep_waiting=lambda: True):
    """True once `name` is registered with the master (rospy.wait_for_service, no node needed);
    False after `timeout` s or as soon as keep_waiting() is False (e.g. the process that should
    offer it has exited)."""
    import rospy
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and keep_waiting():
        try:
            rospy.wait_for_service(name, timeout=min(1.0, max(0.1, deadline - time.monotonic())))
            return True
        except rospy.ROSException:
            continue
        except OSError:  # the master is not up yet
            time.sleep(0.2)
    return False


def edge_settled_key(status):
    """What changes while the edge's Local-Mapping / Loop-Closing still work on what they were
    given (status: GetEdgeStatus as a dict or a response); None without a status."""
    if not status:
        return None
    get = status.get if isinstance(status, dict) else lambda k: getattr(status, k)
    return (get("inserted"), get("global_map_keyframes"), get("global_map_points"), get("loops_closed"),
            tuple(get("culled_ids") or ()))


def wait_until_steady(read_key, quiet_s, timeout, step=0.5):
    """True once read_key() has returned the same value (not None) for quiet_s seconds; False
    after `timeout` s. For a pipeline that has no idle signal of its own (the edge's status)."""
    deadline = time.monotonic() + timeout
    last, since = None, None
    while time.monotonic() < deadline:
        key = read_key()
        now = time.monotonic()
        if key is None or key != last:
            last, since = key, now
        elif now - since >= quiet_s:
            return True
        time.sleep(step)
    return False


def players_waiting_for(state, robots, edge_service="/edge_slam/edge/status"):
    """What a multi-robot run still waits for before its paused players may start (master
    getSystemState() triple, robot names): each robot's mobile subscribed to its colour and depth
    topics (the mobile subscribes once its vocabulary is loaded), each player's pause service, the
    edge's status service. [] when everything is there."""
    pubs, subs, srvs = state
    subscribed = {topic for topic, nodes in subs if nodes}
    services = {name for name, _ in srvs}
    missing = [] if edge_service in services else [edge_service]
    for r in robots:
        for topic in (f"/{r}/camera/rgb/image_color", f"/{r}/camera/depth/image"):
            if topic not in subscribed:
                missing.append(f"a subscriber of {topic}")
        if f"/{r}/player/pause_playback" not in services:
            missing.append(f"/{r}/player/pause_playback")
    return missing


def release_players(robots, timeout):
    """Waits until every robot's mobile and player and the edge are up, then resumes every paused
    player (rosbag play -\-pause) at once: all robots start together, on an event, not after a
    fixed delay. True when released."""
    import rosgraph
    import rospy
    from std_srvs.srv import SetBool
    master = rosgraph.Master("/release_players")
    deadline = time.monotonic() + timeout
    missing = ["the master"]
    while time.monotonic() < deadline:
        try:
            missing = players_waiting_for(master.getSystemState(), robots)
        except (OSError, rosgraph.MasterException):
            missing = ["the master"]
        if not missing:
            break
        time.sleep(0.2)
    if missing:
        raise RuntimeError(f"still waiting after {timeout:.0f} s for: {', '.join(missing)}")
    # Persistent connections, opened by a first call that changes nothing (pause a paused player):
    # the resuming calls then follow each other within milliseconds.
    proxies = [rospy.ServiceProxy(f"/{r}/player/pause_playback", SetBool, persistent=True) for r in robots]
    for p in proxies:
        p.wait_for_service(timeout=5.0)
        p(True)
    clock = ClockWatch()
    started = time.monotonic()
    for p in proxies:
        p(False)
    spread = time.monotonic() - started
    # Everyone runs on sim time: the edge's update timer and the mobiles' update policy move
    # only if /clock does. Once in a loaded run the clock robot's player played its frames while
    # its /clock stayed at the paused stamp (cause not found); a second resume is the workaround,
    # and a clock that still does not move fails the run here instead of silently.
    for attempt in range(2):
        if clock.advanced_by(0.5, timeout=10.0):
            break
        print(f"bench.ros_util: /clock still at {clock.first} s 10 s after resuming the players: resuming again",
              file=sys.stderr)
        for p in proxies:
            p(True)
            p(False)
    else:
        raise RuntimeError(f"/clock did not advance past {clock.first} s after resuming the players")
    for p in proxies:
        p.close()
    return spread


class ClockWatch:
    """The first /clock value seen and whether a later one passed it by some seconds."""

    def __init__(self):
        import rospy
        from rosgraph_msgs.msg import Clock
        if not rospy.core.is_initialized():  # a caller that is a node already (a rostest check)
            rospy.init_node("release_players", anonymous=True, disable_signals=True)
        self.first = self.last = None
        self._sub = rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=10)

    def _on_clock(self, msg):
        t = msg.clock.to_sec()
        if self.first is None:
            self.first = t
        self.last = t

    def advanced_by(self, seconds, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.first is not None and self.last - self.first >= seconds:
                return True
            time.sleep(0.05)
        return False


def main():
    """Command line for the shell scripts (scripts/eval_split.sh, scripts/eval_multi.sh)."""
    import argparse
    import sys
    ap = argparse.ArgumentParser(prog="python3 -m bench.ros_util", description=__doc__)
    ap.add_argument("command", choices=["edge-settled", "release-players"],
                    help="edge-settled: wait until the edge's status stops changing (quiet for --quiet s); "
                         "release-players: wait until the mobiles of --robots, their paused players and the edge "
                         "are up, then resume every player at once")
    ap.add_argument("--quiet", type=float, default=4.0)
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--robots", nargs="+", default=[], help="release-players: the robots' names (robot1 robot2 ...)")
    a = ap.parse_args()
    if a.command == "release-players":
        if not a.robots:
            ap.error("release-players needs --robots")
        try:
            spread = release_players(a.robots, a.timeout)
        except Exception as e:  # still waiting, or a service call failed
            print(f"bench.ros_util: release-players: {e}", file=sys.stderr)
            sys.exit(1)
        print(f"bench.ros_util: {len(a.robots)} players resumed within {spread * 1000:.0f} ms", file=sys.stderr)
        sys.exit(0)
    ok = wait_until_steady(lambda: edge_settled_key(rosservice_call("/edge_slam/edge/status")), a.quiet, a.timeout)
    if not ok:
        print(f"bench.ros_util: the edge did not settle within {a.timeout:.0f} s", file=sys.stderr)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
