#!/usr/bin/env bash
# make fuzz: builds the libFuzzer targets (edge_slam_common/fuzz/) with clang in build_fuzz/,
# writes seed corpora made in code, and runs every target for FUZZ_SECONDS (default 60).
# A crash, leak, sanitizer report or timeout fails the run; the reproducer is left in
# build_fuzz/artifacts/<target>/. Ends with "N passed, N failed, 0 skipped".
#   FUZZ_SECONDS=60  FUZZ_TARGETS="fuzz_keyframe_message ..."  (default: all)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
help_on_request "$@"
cd "$ROOT"
command -v clang++ >/dev/null || die "clang++ not found: run 'make setup' (installs clang, libclang-rt-14-dev)"
BUILD="$ROOT/build_fuzz"
SECONDS_PER_TARGET="${FUZZ_SECONDS:-60}"
mkdir -p "$BUILD/msgs/edge_slam_msgs" "$BUILD/msgs_new" "$BUILD/logs"

say "generating edge_slam_msgs C++ headers (gencpp)"
for msg in edge_slam_msgs/msg/*.msg; do
  /usr/bin/python3 /usr/lib/gencpp/gen_cpp.py "$msg" -p edge_slam_msgs \
    -Iedge_slam_msgs:"$ROOT/edge_slam_msgs/msg" -Igeometry_msgs:/usr/share/geometry_msgs/msg \
    -Istd_msgs:/usr/share/std_msgs/msg -o "$BUILD/msgs_new" -e /usr/share/gencpp
done
for header in "$BUILD"/msgs_new/*.h; do  # replace only changed headers: no needless rebuilds
  cmp -s "$header" "$BUILD/msgs/edge_slam_msgs/$(basename "$header")" || cp "$header" "$BUILD/msgs/edge_slam_msgs/"
done

say "building the fuzz targets (log: $BUILD/logs/build.log)"
if ! { cmake -S edge_slam_common/fuzz -B "$BUILD/cmake" -DCMAKE_CXX_COMPILER=clang++ \
         -DCMAKE_BUILD_TYPE=None -DMSG_INCLUDE_DIR="$BUILD/msgs" &&
       cmake --build "$BUILD/cmake" -j"${BUILD_JOBS:-2}"; } > "$BUILD/logs/build.log" 2>&1; then
  tail -30 "$BUILD/logs/build.log"
  echo "0 passed, 1 failed, 0 skipped"
  exit 1
fi

CORPUS="$BUILD/corpus"
"$BUILD/cmake/make_seeds" "$CORPUS"
TARGETS="${FUZZ_TARGETS:-$(cd "$BUILD/cmake" && ls fuzz_* | tr '\n' ' ')}"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
passed=0
failed=0
for target in $TARGETS; do
  seeds="$CORPUS/${target#fuzz_}"
  work="$BUILD/work/$target"
  artifacts="$BUILD/artifacts/$target"
  mkdir -p "$work" "$artifacts"
  log="$BUILD/logs/$target.log"
  say "$target: ${SECONDS_PER_TARGET} s (seeds: $seeds)"
  # One process, one job: the machine is shared. -rss_limit_mb bounds memory per input too.
  if "$BUILD/cmake/$target" -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 \
       -print_final_stats=1 -artifact_prefix="$artifacts/" "$work" "$seeds" > "$log" 2>&1; then
    passed=$((passed + 1))
    status=ok
  else
    failed=$((failed + 1))
    status=FAIL
  fi
  runs=$(grep -E "^stat::number_of_executed_units" "$log" | awk '{print $2}' || true)
  cov=$(grep -E "^#[0-9]+.*(DONE|pulse|NEW|REDUCE)" "$log" | tail -1 | grep -oE "cov: [0-9]+" || true)
  printf '  %-4s %-28s %s executions, %s, corpus %s files\n' "$status" "$target" "${runs:-?}" "${cov:-cov: ?}" \
    "$(find "$work" -type f | wc -l)"
  [ "$status" = ok ] || grep -m1 -B2 -A20 -E "ERROR: |runtime error:|deadly signal" "$log" | sed 's/^/        /' || true
done
echo "${passed} passed, ${failed} failed, 0 skipped"
[ $failed -eq 0 ]
