#!/usr/bin/env bash
# Runs the SLAM system on a TUM-format folder and adds the ATE to <OUT>/metrics.json.
# Called by `make eval DATASET=<folder> MODE=monolithic|split|multi OUT=<dir>`; builds nothing.
# MODE=multi: several mobiles on one edge, see scripts/eval_multi.sh (ROBOTS, ROBOT_DATASETS, ...).
#   runner: $EDGE_SLAM_RUN, else .ws/devel/lib/edge_slam_common/edge_slam_run
#   ATE:    bench.ate (evo's API in .venv: `evo_ape tum <gt> <traj> -a`), final and online alike
# Extra runner options can be passed in EDGE_SLAM_ARGS (e.g. "--camera config/camera_tum1.yaml").
# Without --vocabulary in EDGE_SLAM_ARGS, a dataset other than bags/synthetic_room gets a
# vocabulary trained on itself (train_vocabulary next to the runner, or
# $EDGE_SLAM_TRAIN_VOCABULARY), cached in results/cache/.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"

DATASET="${DATASET:-bags/synthetic_room}"
MODE="${MODE:-monolithic}"
OUT="${OUT:-results/$(basename "$DATASET")-$MODE}"

if [[ "$MODE" != "monolithic" && "$MODE" != "split" && "$MODE" != "multi" ]]; then
  echo "eval: unknown MODE '$MODE' (monolithic|split|multi)" >&2
  exit 1
fi
if [[ ! -d "$DATASET" ]]; then
  echo "eval: dataset folder '$DATASET' not found" >&2
  exit 1
fi
if [[ ! -f "$DATASET/groundtruth.txt" ]]; then
  echo "eval: '$DATASET/groundtruth.txt' not found: cannot compute the ATE" >&2
  exit 1
fi

VOCAB=""
# Vocabulary: the configured default was trained on the synthetic sequence. For any other
# dataset without --vocabulary, train one from the dataset itself, as the reference ORB-SLAM2
# figures were obtained (vocabulary trained on the sequence itself), into a git-ignored cache
# keyed by the dataset's real path. Derived from the dataset: never commit results/cache/.
if [[ "${EDGE_SLAM_ARGS:-}" != *--vocabulary* ]]; then
  SYNTH_RGB=$(realpath -e bags/synthetic_room/rgb.txt 2>/dev/null || true)
  if [[ "$(realpath -e "$DATASET/rgb.txt" 2>/dev/null || true)" != "$SYNTH_RGB" || -z "$SYNTH_RGB" ]]; then
    TRAIN="${EDGE_SLAM_TRAIN_VOCABULARY:-.ws/devel/lib/edge_slam_common/train_vocabulary}"
    KEY=$(realpath "$DATASET" | sha1sum | cut -c1-12)
    VOCAB="results/cache/vocabulary-$(basename "$DATASET")-$KEY.bin"
    if [[ ! -s "$VOCAB" ]]; then
      if [[ ! -x "$TRAIN" ]]; then
        echo "eval: vocabulary trainer '$TRAIN' not found; build first or set EDGE_SLAM_TRAIN_VOCABULARY" >&2
        exit 1
      fi
      echo "eval: no --vocabulary given and $DATASET is not the synthetic sequence: training a vocabulary" \
           "from the dataset itself (every 3rd frame), as for the reference ORB-SLAM2 run -> $VOCAB" \
           "(cached, git-ignored, never commit it)" >&2
      mkdir -p results/cache
      "$TRAIN" --out "$VOCAB.tmp" --every 3 "$DATASET" >&2
      mv "$VOCAB.tmp" "$VOCAB"
    else
      echo "eval: using the vocabulary trained on $DATASET itself: $VOCAB (cached)" >&2
    fi
  fi
fi

if [[ "$MODE" == "split" || "$MODE" == "multi" ]]; then
  # The same camera and vocabulary choice as the runner's: --camera/--vocabulary in EDGE_SLAM_ARGS,
  # else <dataset>/camera.yaml (fr1 folders: config/camera_tum1.yaml) and the default vocabulary.
  arg_of() { sed -nE "s/.*--$1[ =]([^ ]+).*/\1/p" <<< "${EDGE_SLAM_ARGS:-}"; }
  CAMERA=$(arg_of camera); VOCABULARY=$(arg_of vocabulary)
  if [[ -z "$CAMERA" ]]; then
    CAMERA="$DATASET/camera.yaml"
    case "$(basename "$DATASET")" in *fr1*|*freiburg1*) [[ -f "$CAMERA" ]] || CAMERA=config/camera_tum1.yaml ;; esac
  fi
  VOCABULARY="${VOCABULARY:-${VOCAB:-bags/vocabulary_synthetic.bin}}"
  [[ "$VOCABULARY" = /* ]] || VOCABULARY="$PWD/$VOCABULARY"
  if [[ "$MODE" == "multi" ]]; then   # its own figures and metrics.json (bench.multi_eval)
    DATASET="$DATASET" OUT="$OUT" CAMERA="$CAMERA" VOCABULARY="$VOCABULARY" exec bash scripts/eval_multi.sh
  fi
  DATASET="$DATASET" OUT="$OUT" CAMERA="$CAMERA" VOCABULARY="$VOCABULARY" bash scripts/eval_split.sh
else
  RUN="${EDGE_SLAM_RUN:-.ws/devel/lib/edge_slam_common/edge_slam_run}"
  if [[ ! -x "$RUN" ]]; then
    echo "eval: runner '$RUN' not found; build first (make build) or set EDGE_SLAM_RUN" >&2
    exit 1
  fi

  ARGS=(--dataset "$DATASET" --out "$OUT")
  # TUM freiburg1 folders carry no camera.yaml: use the shipped fr1 calibration.
  if [[ ! -f "$DATASET/camera.yaml" && "${EDGE_SLAM_ARGS:-}" != *--camera* ]]; then
    case "$(basename "$DATASET")" in
      *fr1*|*freiburg1*) echo "eval: $DATASET has no camera.yaml, using config/camera_tum1.yaml" >&2
                         ARGS+=(--camera config/camera_tum1.yaml) ;;
    esac
  fi

  mkdir -p "$OUT"
  # shellcheck disable=SC2086
  "$RUN" "${ARGS[@]}" ${VOCAB:+--vocabulary "$VOCAB"} ${EDGE_SLAM_ARGS:-}
fi

TRAJ="$OUT/trajectory.txt"
if [[ $(grep -vc '^#' "$TRAJ" || true) -lt 3 ]]; then
  echo "eval: fewer than 3 tracked poses in $TRAJ: no ATE" >&2
  exit 1
fi

# Every ATE (final, and for split the poses as tracked) from one tool with one association
# tolerance: bench.ate, evo's API in the venv (`evo_ape tum <gt> <traj> -a`, max_diff 0.01 s).
[[ -x .venv/bin/python3 ]] || { echo "eval: no .venv (evo): run 'make setup' first" >&2; exit 1; }
ate() { PYTHONPATH="$PWD/scripts${PYTHONPATH:+:$PYTHONPATH}" .venv/bin/python3 -m bench.ate "$@" --json; }
ATE_JSON=$(ate "$DATASET/groundtruth.txt" "$TRAJ")

/usr/bin/python3 - "$OUT/metrics.json" "$ATE_JSON" <<'PY'
import json, sys
path, ate = sys.argv[1], json.loads(sys.argv[2])
with open(path) as f:
    m = json.load(f)
m.update(ate)
with open(path, "w") as f:
    json.dump(m, f, indent=2)
    f.write("\n")
print(f"ATE RMSE {ate['ate_rmse_m'] * 100:.2f} cm ({ate['ate_tool']}), "
      f"frames tracked {m['frames_tracked']}/{m['frames']}, "
      f"tracking median {m['tracking_ms']['median']:.1f} ms -> {path}")
PY

if [[ "$MODE" == "monolithic" && -f "$OUT/trajectory_online.txt" ]]; then
  # The poses as tracked, before later BA and loop corrections: what a robot navigates on.
  ONLINE_JSON=$(ate "$DATASET/groundtruth.txt" "$OUT/trajectory_online.txt")
  /usr/bin/python3 - "$OUT/metrics.json" "$ONLINE_JSON" <<'PY'
import json, sys
path, ate = sys.argv[1], json.loads(sys.argv[2])
m = json.load(open(path))
m["ate_online_rmse_m"] = ate["ate_rmse_m"]
m["ate_online_pairs"] = ate["ate_pairs"]
json.dump(m, open(path, "w"), indent=2)
print(f"monolithic: ATE of the poses as tracked {ate['ate_rmse_m'] * 100:.2f} cm; KeyFrames created "
      f"{m.get('keyframes_created')}, kept {m.get('keyframes')}; "
      f"loops closed {m.get('loops_closed')}; lost {m.get('times_lost')} times")
PY
fi

if [[ "$MODE" == "split" && -f "$OUT/trajectory_online.txt" ]]; then
  # The poses as the mobile tracked them (before the edge's later optimisation and loop closure),
  # and their largest jump at an installed Local-Map update (mobile_stats.csv "update" rows).
  ONLINE_JSON=$(ate "$DATASET/groundtruth.txt" "$OUT/trajectory_online.txt" --update-stamps-from "$OUT/mobile_stats.csv")
  /usr/bin/python3 - "$OUT/metrics.json" "$ONLINE_JSON" <<'PY'
import json, sys
path, ate = sys.argv[1], json.loads(sys.argv[2])
m = json.load(open(path))
m["ate_online_rmse_m"] = ate["ate_rmse_m"]
m["ate_online_pairs"] = ate["ate_pairs"]
m["update_jump_max_m"] = ate["update_jump_max_m"]
m["update_jumps"] = ate["update_jumps"]
# The split's KeyFrame accounting in one place: made on the mobile, inserted / refused on the edge.
k = m.get("edge", {}).get("keyframes", {})
m["keyframes_made"] = m.get("keyframes")
m["keyframes_inserted"] = k.get("inserted")
m["keyframes_refused_condition1"] = k.get("rejected_condition1")
m["keyframes_refused_condition2"] = k.get("rejected_condition2")
json.dump(m, open(path, "w"), indent=2)
u = m.get("updates", {})
jump = ate["update_jump_max_m"]
print(f"split: ATE of the poses as tracked {ate['ate_rmse_m'] * 100:.2f} cm; largest jump at an update "
      f"{'n/a' if jump is None else '%.2f cm' % (jump * 100)} over {len(ate['update_jumps'])} updates installed; "
      f"updates accepted {u.get('accepted')}/{u.get('received')} (sent early on divergence "
      f"{m.get('edge', {}).get('updates_on_divergence', 0)}); Local-Map peak {m.get('local_map_peak')} KeyFrames")
print(f"split: KeyFrames made {m['keyframes_made']}, inserted on the edge {m['keyframes_inserted']}, refused by "
      f"condition 1 {m['keyframes_refused_condition1']} / condition 2 {m['keyframes_refused_condition2']}; "
      f"edge loops closed {m.get('loops_closed')}; lost {m.get('times_lost')} times")
PY
fi
