#!/usr/bin/env bash
# Pairs of `make eval MODE=split` run back to back: "before" = a workspace built at the commit
# before the change (EDGE_SLAM_WS), "after" = the repo's own .ws. Usage, from the repo root:
#   docs/benchmarks/2026-12-08/keypoint_block/run_pairs.sh <before .ws> <out folder> <pairs> [dataset] [mode]
set -euo pipefail
BEFORE_WS=$1 OUT=$2 PAIRS=$3 DATASET=${4:-../shared/datasets/tum_fr1_rpy} MODE=${5:-split}
export PATH=/usr/bin:$PATH
mkdir -p "$OUT"
for i in $(seq 1 "$PAIRS"); do
  EDGE_SLAM_WS=$BEFORE_WS make eval MODE="$MODE" DATASET="$DATASET" OUT="$OUT/r${i}_before" > "$OUT/r${i}_before.log" 2>&1
  make eval MODE="$MODE" DATASET="$DATASET" OUT="$OUT/r${i}_after" > "$OUT/r${i}_after.log" 2>&1
done
