#!/usr/bin/env bash
# ASan + UBSan run (make test-asan): builds edge_slam_msgs + edge_slam_common (core, bridge,
# their gtests and edge_slam_run) in its own catkin workspace build_asan/ws with the sanitizers,
# runs every unit test, then one monolithic integration run on the first frames of the
# synthetic sequence. Any sanitizer report stops the process that made it (halt_on_error) and
# counts as a failure. Ends with "N passed, N failed, 0 skipped".
#   ASAN_FRAMES=200 (frames of the integration run), BUILD_ONLY=1 (build, run nothing)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"
WS="$ROOT/build_asan/ws"
LOGS="$ROOT/build_asan/logs"
mkdir -p "$WS/src" "$LOGS"
ln -sfn "$ROOT/edge_slam_msgs" "$WS/src/edge_slam_msgs"
ln -sfn "$ROOT/edge_slam_common" "$WS/src/edge_slam_common"
[ -e "$WS/src/CMakeLists.txt" ] || ln -s /usr/share/catkin/cmake/toplevel.cmake "$WS/src/CMakeLists.txt"

# -O1 keeps the run time bearable; no NDEBUG, so Eigen's own assertions are live too.
SAN="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
say "building with ASan + UBSan in $WS (log: $LOGS/build.log)"
set +u
# shellcheck disable=SC1091
source /opt/ros/*/setup.bash 2>/dev/null || true
set -u
if ! (cd "$WS" && catkin_make -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS="-O1 -g1 $SAN" \
        -DCMAKE_EXE_LINKER_FLAGS="$SAN" -DCMAKE_SHARED_LINKER_FLAGS="$SAN" \
        -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
        -j"${BUILD_JOBS:-2}" edge_slam_run tests) > "$LOGS/build.log" 2>&1; then
  tail -30 "$LOGS/build.log"
  echo "0 passed, 1 failed, 0 skipped"
  exit 1
fi
[ "${BUILD_ONLY:-0}" = 1 ] && { say "built (BUILD_ONLY=1)"; exit 0; }

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$ROOT/scripts/lsan_suppressions.txt:print_suppressions=0"
set +u
# shellcheck disable=SC1091
source "$WS/devel/setup.bash"
set -u
passed=0
failed=0
run_one() {  # name, log, command...
  local name="$1" log="$2"
  shift 2
  if "$@" > "$log" 2>&1 && ! grep -qE "ERROR: (Address|Leak)Sanitizer|runtime error:" "$log"; then
    passed=$((passed + 1))
    printf '  ok    %s\n' "$name"
  else
    failed=$((failed + 1))
    printf '  FAIL  %s (log: %s)\n' "$name" "$log"
    grep -m1 -A12 -E "ERROR: (Address|Leak)Sanitizer|runtime error:|\[  FAILED  \]" "$log" | sed 's/^/        /' || true
  fi
}
say "unit tests"
mapfile -t TESTS < <(find "$WS/devel" "$WS/build" -type f -executable -name 'test_*' ! -name '*.py' | sort -u)
[ ${#TESTS[@]} -gt 0 ] || die "no test binaries found under $WS"
cd "$ROOT/edge_slam_common"  # core tests read fixtures relative to the package, as catkin runs them
for t in "${TESTS[@]}"; do
  run_one "$(basename "$t")" "$LOGS/$(basename "$t").log" "$t"
done
cd "$ROOT"

say "integration: edge_slam_run monolithic, first ${ASAN_FRAMES:-200} frames of bags/synthetic_room"
RUN_BIN=$(find "$WS/devel" -type f -executable -name edge_slam_run | head -1)
[ -d bags/synthetic_room ] || bash scripts/make_dataset.sh
rm -rf "$ROOT/build_asan/run"
run_one "edge_slam_run (monolithic, ${ASAN_FRAMES:-200} frames)" "$LOGS/edge_slam_run.log" \
  "$RUN_BIN" --dataset bags/synthetic_room --vocabulary bags/vocabulary_synthetic.bin \
  --out "$ROOT/build_asan/run" --max-frames "${ASAN_FRAMES:-200}" --pace none
[ -f "$ROOT/build_asan/run/metrics.json" ] && sed 's/^/        /' "$ROOT/build_asan/run/metrics.json" | head -12
cases=$(cat "$LOGS"/test_*.log | grep -E "^\[  PASSED  \] [0-9]+ test" | awk '{n += $4} END {print n + 0}')
say "gtest cases passed under the sanitizers: $cases"
echo "${passed} passed, ${failed} failed, 0 skipped"
[ $failed -eq 0 ]
