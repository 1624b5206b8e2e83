"""The skeleton the recorders share (net_recorder, odometry_recorder, test/delivery/stats_probe):
wait for the ROS master, start an anonymous node, subscribe, run until SIGINT/SIGTERM."""
import signal
import sys
import time

import rosgraph
import rospy


def run_recorder(name, subscribe, master_timeout=120.0, stop_when_master_gone=True):
    """Waits for the master (exits with an error after master_timeout seconds; None: forever),
    starts node `name`, calls subscribe() to create its subscribers, then returns on SIGINT or
    SIGTERM, or when the master goes away if stop_when_master_gone (a recorder that must
    outlive a cut link keeps it False)."""
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    deadline = None if master_timeout is None else time.monotonic() + master_timeout
    while not rosgraph.is_master_online():
        if stop:
            return
        if deadline is not None and time.monotonic() > deadline:
            sys.exit(f"{name}: no ROS master")
        time.sleep(0.2)
    rospy.init_node(name, anonymous=True, disable_signals=True)
    subscribe()
    while not stop and (not stop_when_master_gone or rosgraph.is_master_online()):
        time.sleep(0.2)
