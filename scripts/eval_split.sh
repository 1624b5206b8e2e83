#!/usr/bin/env bash
# MODE=split of `make eval`: the mobile and edge nodelets (two processes, launch/edge_slam.launch)
# on the dataset replayed by rosbag at real time; writes into $OUT the same metrics.json as the
# monolithic runner plus the split's own figures, the final trajectory (frames re-anchored on the
# edge's final KeyFrames, as monolithic/ORB-SLAM2 save theirs), the as-tracked trajectory, the
# Local-Map size over time and both sides' per-event CSVs (read by column name: io/event_log.h).
# Called by scripts/eval.sh.
#   env: DATASET (TUM folder) OUT CAMERA VOCABULARY (resolved by eval.sh);
#        SLAM_CONFIG (default config/slam.yaml);
#        SPLIT_SOURCE=folder plays the folder live (tum_player) instead of its bag (long sequences);
#        SPLIT_LAUNCH_ARGS extra roslaunch arguments (e.g. manager_prefix:="..." for a debugger);
#        EDGE_SLAM_WS another workspace to run (e.g. a sanitizer build, scripts/common.sh)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"
ros_env

name=$(basename "$DATASET")
BAG="$DATASET.bag"
if [[ "${SPLIT_SOURCE:-bag}" == folder ]]; then   # played live from the folder (tum_player): no bag
  SOURCE=(folder:="$(cd "$DATASET" && pwd)")
elif [[ ! -f "$BAG" ]]; then   # a TUM folder without its bag: convert once into a git-ignored cache
  BAG="results/cache/$name.bag"
  if [[ ! -f "$BAG" || "$DATASET/rgb.txt" -nt "$BAG" ]]; then
    mkdir -p results/cache
    say "converting $DATASET to $BAG (rosbag of the TUM topics; once)"
    rosrun edge_slam_common tum_to_bag "$DATASET" "$BAG" >&2
  fi
fi
[[ "$BAG" = /* ]] || BAG="$ROOT/$BAG"
[[ "${SPLIT_SOURCE:-bag}" == folder ]] || SOURCE=(bag:="$BAG")
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
[[ "$CAMERA" = /* ]] || CAMERA="$ROOT/$CAMERA"
rm -f "$OUT"/{mobile,edge}_{stats.csv,metrics.json} "$OUT"/{edge_keyframes,mobile_anchors,trajectory,trajectory_online}.txt

export ROS_MASTER_URI="http://localhost:${EVAL_ROS_PORT:-11391}"   # its own master: never disturbs another ROS session
roscore -p "${EVAL_ROS_PORT:-11391}" > "$OUT/roscore.log" 2>&1 &
core_pid=$!
launch_pid=""
stop_ros() {
  set +e
  [[ -n "$launch_pid" ]] && kill -INT "$launch_pid" 2>/dev/null && sleep 3
  kill "$core_pid" 2>/dev/null
  wait 2>/dev/null
  return 0
}
trap stop_ros EXIT
for _ in $(seq 50); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done

say "split: mobile + edge nodelets on ${SOURCE[0]#*:=} (real time; logs in $OUT/launch.log)"
# Every frame is tracked (deep image queues), as the monolithic runner tracks every frame: the
# accuracy comparison is like for like; SPLIT_IMAGE_QUEUE=2 gives a live camera's frame dropping.
roslaunch launch/edge_slam.launch "${SOURCE[@]}" image_queue_size:="${SPLIT_IMAGE_QUEUE:-1000}" \
  slam_config:="$(realpath "${SLAM_CONFIG:-config/slam.yaml}")" camera_config:="$CAMERA" vocabulary:="$VOCABULARY" \
  out:="$OUT" exit_with_bag:=false ${SPLIT_LAUNCH_ARGS:-} > "$OUT/launch.log" 2>&1 &
launch_pid=$!

# The bag is over when rosbag play has exited; then the edge finishes what it was given.
player_running() { [[ $(launch_children_named "$launch_pid" player) -gt 0 ]]; }
for _ in $(seq 120); do player_running && break; sleep 0.5; done
player_running || die "the player (rosbag play / tum_player) did not start: see $OUT/launch.log"
while player_running; do
  kill -0 $launch_pid 2>/dev/null || die "the launch ended early: see $OUT/launch.log"
  sleep 2
done
say "bag finished; waiting for the edge's Local-Mapping and Loop-Closing to settle"
PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m bench.ros_util edge-settled --timeout 120 \
  || say "the edge was still changing after 120 s; writing what it has"
kill -INT $launch_pid; wait $launch_pid 2>/dev/null || true
launch_pid=""

[[ -f "$OUT/mobile_metrics.json" && -f "$OUT/edge_metrics.json" ]] || die "the nodelets wrote no metrics: see $OUT/launch.log"
.ws/devel/lib/edge_slam_common/compose_trajectory --anchors "$OUT/mobile_anchors.txt" \
  --keyframes "$OUT/edge_keyframes.txt" --out "$OUT/trajectory.txt"

# One metrics.json: the mobile's figures on top (same keys as monolithic), the edge's module
# timings beside them, the edge's own figures under "edge", the Local-Map size over time.
/usr/bin/python3 - "$OUT" "$DATASET" <<'PY'
import csv, json, os, sys
out, dataset = sys.argv[1], sys.argv[2]
m = json.load(open(os.path.join(out, "mobile_metrics.json")))
e = json.load(open(os.path.join(out, "edge_metrics.json")))
m["dataset"] = dataset
for k in ("local_mapping", "local_mapping_ms", "local_ba_ms", "loop_detection_ms", "loop_correction_ms",
          "full_ba_ms", "loops_closed", "full_ba_runs", "loops"):
    if k in e:
        m[k] = e[k]
m["map_points"] = e.get("global_map_points")
m["edge"] = e
series, last = [], None
with open(os.path.join(out, "mobile_stats.csv")) as f:
    for row in csv.DictReader(f):
        if row["event"] != "frame":
            continue
        t, n = float(row["data_time"]), int(row["map_keyframes"])
        if last is None or t - last >= 1.0 or (series and n != series[-1][1]):
            series.append([round(t, 3), n])
            last = t
m["local_map_keyframes_over_time"] = series
json.dump(m, open(os.path.join(out, "metrics.json"), "w"), indent=2)
PY
