#!/usr/bin/env bash
# Data-race check of the monolithic system (issue 4): builds the core with ThreadSanitizer in
# build_tsan/ (core only, no ROS), runs edge_slam_run -- Tracking, Local-Mapping and
# Loop-Closing as three threads -- on the synthetic sequence, and fails on any report.
#   scripts/tsan.sh [--every K] [--max-frames N] [--dataset <TUM folder>]
# Defaults: every frame of bags/synthetic_room (frames unpaced: TSan makes each one ~10x
# slower, so real-time pacing would only change timing). Exit status: 0 when the run finished
# with no "WARNING: ThreadSanitizer" report, 1 otherwise; the reports are in
# results/tsan/tsan.log. BUILD_JOBS (default 2) sets the build parallelism.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"

DATASET=bags/synthetic_room
RUN_ARGS=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --every|--max-frames) [[ $# -ge 2 ]] || die "$1 needs a value"; RUN_ARGS+=("$1" "$2"); shift 2 ;;
    --dataset) [[ $# -ge 2 ]] || die "$1 needs a value"; DATASET="$2"; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) die "tsan.sh: unknown argument '$1'" ;;
  esac
done
[[ -f "$DATASET/rgb.txt" ]] || die "dataset '$DATASET' not found (run 'make dataset' for the synthetic one)"
VOCAB=bags/vocabulary_synthetic.bin
[[ -f "$VOCAB" ]] || die "vocabulary '$VOCAB' not found (run 'make dataset')"

BUILD=build_tsan
OUT=results/tsan
mkdir -p "$OUT"
say "building the core with -fsanitize=thread in $BUILD/ (logs in $OUT/)"
cmake -S edge_slam_common -B "$BUILD" -DEDGE_SLAM_CORE_ONLY=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="-fsanitize=thread -g -O1" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" > "$OUT/cmake.log" 2>&1 || { tail -20 "$OUT/cmake.log"; die "cmake failed"; }
cmake --build "$BUILD" -j"${BUILD_JOBS:-2}" --target edge_slam_run > "$OUT/build.log" 2>&1 ||
  { grep -E "error" "$OUT/build.log" | head -20; die "build failed (log: $OUT/build.log)"; }

LOG="$OUT/tsan.log"
say "running edge_slam_run (monolithic, 3 threads) on $DATASET under TSan -> $LOG"
set +e
# history_size: longer access histories, so reports carry both stacks; tsan.supp silences
# third-party libraries only (each entry says why).
TSAN_OPTIONS="halt_on_error=0 second_deadlock_stack=1 history_size=4 suppressions=$ROOT/scripts/tsan.supp ${TSAN_OPTIONS:-}" \
  "$BUILD/edge_slam_run" --dataset "$DATASET" --vocabulary "$VOCAB" --out "$OUT" --pace none \
  "${RUN_ARGS[@]}" > "$LOG" 2>&1
rc=$?
set -e
warnings=$(grep -c "WARNING: ThreadSanitizer" "$LOG" || true)
grep -E "^frames [0-9]+, tracked" "$LOG" || true
grep -E "^SUMMARY: ThreadSanitizer" "$LOG" | sort | uniq -c | sort -rn | head -20 || true
echo "tsan: runner exit status $rc, $warnings ThreadSanitizer warning(s) (log: $LOG)"
[[ $rc -eq 0 && $warnings -eq 0 ]]
