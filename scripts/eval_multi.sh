#!/usr/bin/env bash
# MODE=multi of `make eval`: several mobiles on one edge (launch/edge_slam.launch robots:=N, one
# private roscore), each robot replaying its own data at real time, all starting together; writes
# into $OUT the edge's outputs and metrics.json, and into $OUT/robotK/ robot K's (mobile CSV and
# metrics, trajectory_online.txt in its own map frame, mobile_anchors.txt, trajectory.txt: its
# final trajectory in the world frame, composed by compose_trajectory from its anchors and the
# edge's KeyFrames, groundtruth.txt on the time it was played at). Figures (bench.multi_eval):
# per-robot online ATE (own frame, own alignment), the combined final ATE (all robots' final
# trajectories together, ONE alignment against all ground truths), the number of map merges.
# Called by scripts/eval.sh (`make eval MODE=multi DATASET=<TUM folder>`).
#   robots: ROBOT_DATASETS="<folder1> <folder2> ..." (2-4 TUM folders) if given; else, for the
#           synthetic room, robot1 = DATASET and robot2 = $SYNTH_ROBOT2 (bags/synthetic_room_robot2);
#           else DATASET cut into ROBOTS (2) consecutive parts (scripts/split_dataset.py, overlap
#           MULTI_OVERLAP colour frames, default 0) in results/cache/: robot 2 starts mid-sequence.
#   clock:  all robots start at once on one /clock (edge_slam.launch says why): robot K's stamps
#           are moved by (robot 1's first stamp - robot K's first stamp). A robot is played by
#           rosbag from <folder>.bag when that exists and needs no move (< 0.5 s), else from its
#           folder converted once (tum_to_bag --time-offset) into results/cache/ (git-ignored);
#           MULTI_SOURCE=folder plays the folders live instead (tum_player --time-offset: decodes
#           as it goes, late on a loaded machine). The clock robot is the one whose data ends last.
#   env: DATASET OUT CAMERA VOCABULARY (resolved by eval.sh); SLAM_CONFIG (config/slam.yaml);
#        MULTI_LAUNCH_ARGS extra roslaunch arguments; EVAL_ROS_PORT (default 11392);
#        EDGE_SLAM_WS another workspace to run (scripts/common.sh)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"
ros_env

: "${DATASET:?DATASET (a TUM folder) is required}" "${OUT:?OUT is required}" "${CAMERA:?}" "${VOCABULARY:?}"
ROBOTS="${ROBOTS:-2}"
SYNTH_ROBOT2="${SYNTH_ROBOT2:-bags/synthetic_room_robot2}"
MULTI_OVERLAP="${MULTI_OVERLAP:-0}"
MULTI_SOURCE="${MULTI_SOURCE:-auto}"
PORT="${EVAL_ROS_PORT:-11392}"
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
[[ "$CAMERA" = /* ]] || CAMERA="$ROOT/$CAMERA"
case "$MULTI_SOURCE" in auto|folder) ;; *) die "MULTI_SOURCE must be auto or folder (not '$MULTI_SOURCE')" ;; esac
[[ "$MULTI_OVERLAP" =~ ^[0-9]+$ ]] || die "MULTI_OVERLAP must be a number of frames (not '$MULTI_OVERLAP')"

# ---- the robots' data -----------------------------------------------------------------------
is_synthetic() { [[ "$(realpath -e "$1/rgb.txt" 2>/dev/null)" == "$(realpath -e bags/synthetic_room/rgb.txt 2>/dev/null || echo none)" ]]; }
if [[ -n "${ROBOT_DATASETS:-}" ]]; then
  read -ra DATASETS <<< "$ROBOT_DATASETS"
elif is_synthetic "$DATASET"; then
  [[ -d "$SYNTH_ROBOT2" ]] || die "robot 2's data '$SYNTH_ROBOT2' not found (SYNTH_ROBOT2: the synthetic room's second robot)"
  DATASETS=("$DATASET" "$SYNTH_ROBOT2")
else
  [[ "$ROBOTS" =~ ^[234]$ ]] || die "ROBOTS must be 2, 3 or 4 (not '$ROBOTS')"
  name=$(basename "$DATASET")
  DATASETS=()
  for k in $(seq "$ROBOTS"); do
    DATASETS+=("results/cache/${name}_part${k}of${ROBOTS}$([[ $MULTI_OVERLAP == 0 ]] || echo "_overlap$MULTI_OVERLAP")")
  done
  stale=0
  for d in "${DATASETS[@]}"; do [[ -f "$d/rgb.txt" && ! "$DATASET/rgb.txt" -nt "$d/rgb.txt" ]] || stale=1; done
  if [[ $stale == 1 ]]; then
    mkdir -p results/cache
    say "cutting $DATASET into $ROBOTS parts (one per robot; overlap $MULTI_OVERLAP frames) in results/cache/ (git-ignored; derived from the dataset: never commit it)"
    /usr/bin/python3 scripts/split_dataset.py "$DATASET" "${DATASETS[@]}" --overlap "$MULTI_OVERLAP" --force >&2
  fi
fi
N=${#DATASETS[@]}
(( N >= 2 && N <= 4 )) || die "a multi-robot run takes 2 to 4 robots (got $N)"
for d in "${DATASETS[@]}"; do
  [[ -d "$d" ]] || die "robot data folder '$d' not found"
  for f in rgb.txt depth.txt groundtruth.txt; do [[ -f "$d/$f" ]] || die "'$d/$f' not found (each robot needs a TUM folder with ground truth)"; done
done

# First and last colour stamps of each robot: the time offsets and the clock robot.
read -ra SPAN <<< "$(/usr/bin/python3 - "${DATASETS[@]}" <<'PY'
import os, sys
sys.path.insert(0, os.path.join(os.getcwd(), 'edge_slam_common', 'python'))
from edge_slam_common.tum import InputError, list_seconds
try:
    out = []
    for d in sys.argv[1:]:
        s = list_seconds(os.path.join(d, 'rgb.txt'))
        if not s:
            raise InputError('%s/rgb.txt: no frames' % d)
        out += ['%.6f' % s[0], '%.6f' % s[-1]]
    print(' '.join(out))
except InputError as e:
    sys.exit('eval_multi: %s' % e)
PY
)"
(( ${#SPAN[@]} == 2 * N )) || die "could not read the robots' stamps"
LAUNCH_ROBOT_ARGS=()
OFFSETS=(); SOURCES=(); SOURCE_PATHS=()
clock_robot=1; clock_end=""
for k in $(seq "$N"); do
  d="${DATASETS[$((k-1))]}"
  offset=$(awk -v a="${SPAN[0]}" -v b="${SPAN[$((2*k-2))]}" 'BEGIN { printf "%.6f", a - b }')
  end=$(awk -v e="${SPAN[$((2*k-1))]}" -v o="$offset" 'BEGIN { printf "%.6f", e + o }')
  needs_move=$(awk -v o="$offset" 'BEGIN { print (o < -0.5 || o > 0.5) ? 1 : 0 }')
  if [[ "$MULTI_SOURCE" == folder ]]; then   # played live by tum_player, its stamps moved as it goes
    source=folder; path=$(realpath "$d"); LAUNCH_ROBOT_ARGS+=("folder$k:=$path" "time_offset$k:=$offset")
  else   # a bag: the robot's own when it needs no move, else its folder converted once onto robot1's time
    bag="$d.bag"
    if [[ $needs_move == 1 || ! -f "$bag" ]]; then
      bag="results/cache/$(basename "$d")$([[ $needs_move == 0 ]] || echo "_moved$offset").bag"
      if [[ ! -f "$bag" || "$d/rgb.txt" -nt "$bag" ]]; then
        mkdir -p results/cache
        say "converting $d to $bag (rosbag of the TUM topics, stamps moved by $offset s; once, git-ignored)"
        rosrun edge_slam_common tum_to_bag "$d" "$bag" --time-offset "$offset" >&2
      fi
    fi
    [[ $needs_move == 1 ]] || offset=0.000000
    source=bag; path=$(realpath "$bag"); LAUNCH_ROBOT_ARGS+=("bag$k:=$path" "folder$k:=")
  fi
  OFFSETS+=("$offset"); SOURCES+=("$source"); SOURCE_PATHS+=("$path")
  if [[ -z "$clock_end" ]] || awk -v a="$end" -v b="$clock_end" 'BEGIN { exit !(a > b + 1e-6) }'; then
    clock_robot=$k; clock_end=$end
  fi
  say "robot$k: $source $path, stamps moved by $offset s"
done
say "robot$clock_robot publishes /clock (its data ends last)"

# ---- the run --------------------------------------------------------------------------------
for k in $(seq 4); do rm -rf "${OUT:?}/robot$k"; done
rm -f "$OUT"/{edge_stats.csv,edge_metrics.json,edge_keyframes.txt,metrics.json}
export ROS_MASTER_URI="http://localhost:$PORT"   # its own master: never disturbs another ROS session
roscore -p "$PORT" > "$OUT/roscore.log" 2>&1 &
core_pid=$!
launch_pid=""
stop_ros() {
  set +e
  [[ -n "$launch_pid" ]] && kill -INT "$launch_pid" 2>/dev/null && wait "$launch_pid" 2>/dev/null
  kill "$core_pid" 2>/dev/null
  wait 2>/dev/null
  return 0
}
trap stop_ros EXIT
for _ in $(seq 100); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done
rosparam list > /dev/null 2>&1 || die "roscore on port $PORT did not come up: see $OUT/roscore.log"


# The players start paused and are resumed together once every mobile and the edge are up (an
# event, not the players' fixed delay; rosbag play and tum_player both offer ~pause_playback).
PAUSED=true
say "multi: $N mobiles + one edge (real time; logs in $OUT/launch.log)"
roslaunch launch/edge_slam.launch robots:="$N" clock_robot:="$clock_robot" start_paused:=$PAUSED "${LAUNCH_ROBOT_ARGS[@]}" \
  image_queue_size:="${MULTI_IMAGE_QUEUE:-1000}" slam_config:="$(realpath "${SLAM_CONFIG:-config/slam.yaml}")" \
  camera_config:="$CAMERA" vocabulary:="$VOCABULARY" out:="$OUT" exit_with_bag:=false ${MULTI_LAUNCH_ARGS:-} \
  > "$OUT/launch.log" 2>&1 &
launch_pid=$!

# Every player must come up, then all must end; a player that failed is an error.
players_running() {  # prints how many of the robots' players the master knows
  local nodes; nodes=$(rosnode list 2>/dev/null || true)
  local n=0; for k in $(seq "$N"); do grep -qx "/robot$k/player" <<< "$nodes" && n=$((n+1)); done; echo $n
}
player_failed() { grep -E "\[robot[0-9]/player-[0-9]+\] process has died" "$OUT/launch.log" 2>/dev/null | head -1; }
for _ in $(seq 240); do
  [[ $(players_running) == "$N" ]] && break
  kill -0 $launch_pid 2>/dev/null || die "the launch ended early: see $OUT/launch.log"
  [[ -z "$(player_failed)" ]] || die "a player failed: $(player_failed) (see $OUT/launch.log)"
  sleep 0.5
done
[[ $(players_running) == "$N" ]] || die "not every player (rosbag play / tum_player) started: see $OUT/launch.log"
if [[ $PAUSED == true ]]; then
  ROBOT_NAMES=(); for k in $(seq "$N"); do ROBOT_NAMES+=("robot$k"); done
  PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m bench.ros_util release-players \
    --robots "${ROBOT_NAMES[@]}" --timeout 180 || die "the players could not be started: see $OUT/launch.log"
fi
while [[ $(launch_children_named "$launch_pid" player) != 0 ]]; do
  kill -0 $launch_pid 2>/dev/null || die "the launch ended early: see $OUT/launch.log"
  [[ -z "$(player_failed)" ]] || die "a player failed: $(player_failed) (see $OUT/launch.log)"
  sleep 2
done
say "every robot's data has been played; waiting for the edge's Local-Mapping, Loop-Closing and merging to settle"
PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m bench.ros_util edge-settled --timeout 180 \
  || say "the edge was still changing after 180 s; writing what it has"
kill -INT $launch_pid; wait $launch_pid 2>/dev/null || true
launch_pid=""

[[ -f "$OUT/edge_metrics.json" ]] || die "the edge wrote no metrics: see $OUT/launch.log"
ROBOT_ARGS=()
for k in $(seq "$N"); do
  r="$OUT/robot$k"
  [[ -f "$r/mobile_metrics.json" ]] || die "robot$k's mobile wrote no metrics: see $OUT/launch.log"
  # Its final trajectory in the world frame: its frames re-anchored on the edge's final KeyFrames
  # (the edge writes every robot's KeyFrames in the world frame; KeyFrame ids are per robot).
  if ! .ws/devel/lib/edge_slam_common/compose_trajectory --anchors "$r/mobile_anchors.txt" \
       --keyframes "$OUT/edge_keyframes.txt" --out "$r/trajectory.txt" 2> "$r/compose.log"; then
    say "robot$k: no final trajectory: $(tail -1 "$r/compose.log")"
    rm -f "$r/trajectory.txt"
  fi
  ROBOT_ARGS+=(--robot "robot$k" "$(realpath "${DATASETS[$((k-1))]}")" "${OFFSETS[$((k-1))]}" "${SOURCES[$((k-1))]}")
done

[[ -x .venv/bin/python3 ]] || die "no .venv (evo): run 'make setup' first"
PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}" .venv/bin/python3 -m bench.multi_eval "$OUT" "${ROBOT_ARGS[@]}"
