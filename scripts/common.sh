# Shared shell helpers for the scripts in this folder (sourced, not run).
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Debian's python3 and ROS tools first: the pyenv python3 on PATH has no ROS modules.
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
export ROS_HOME="${ROS_HOME:-$ROOT/.ws/ros_home}"
STAMPS="$ROOT/.stamps"
mkdir -p "$STAMPS"

say() { printf '\033[1m[edge_slam]\033[0m %s\n' "$*" >&2; }
die() { printf '[edge_slam] ERROR: %s\n' "$*" >&2; exit 1; }

# How many node processes named NAME (any namespace) the roslaunch with pid LAUNCH_PID runs
# (roslaunch starts each node as its child). Polled while a bag plays: `rosnode list` is a
# Python process and an XML-RPC round trip each time, and on the 2-core machine those polls
# took a core from the tracking being measured (perf sched, 2026-12-05); pgrep costs nothing.
launch_children_named() { pgrep -c -P "$1" -f "__name:=$2( |\$)" 2>/dev/null || true; }

# Hash of the given files' contents (a stamp: redo a step only when its inputs changed).
inputs_hash() { cat "$@" 2>/dev/null | sha256sum | cut -c1-16; }

ros_env() {
  # EDGE_SLAM_WS: another catkin workspace of these packages (e.g. a sanitizer build); default .ws.
  local ws="${EDGE_SLAM_WS:-$ROOT/.ws}"
  [ -f "$ws/devel/setup.bash" ] || die "workspace not built: run 'make setup' first ($ws)"
  set +u
  # shellcheck disable=SC1091
  source "$ws/devel/setup.bash"
  set -u
  # rospack re-crawls the package path when its cache in ROS_HOME is older than ROS_CACHE_TIMEOUT
  # (60 s), and processes started together (two nodelet managers, their loaders) can then read a
  # half-written cache and fail to find a nodelet's plugin ("Failed to load nodelet"). Crawl once
  # here, and keep that cache for the whole run.
  export ROS_CACHE_TIMEOUT=86400
  rospack plugins --attrib=plugin nodelet > /dev/null 2>&1 || true
}

# A script's --help (or -h) as its first argument: its header comment (the usage), exit status 0.
help_on_request() {
  case "${1:-}" in
    -h|--help) sed -n '2,/^[^#]/{/^#/s/^# \{0,1\}//p}' "${BASH_SOURCE[1]:-$0}"; exit 0 ;;
  esac
}
