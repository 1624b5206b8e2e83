#!/usr/bin/env bash
# `make bench DATASET=<TUM folder or bag> OUT=<dir>`: the benchmark suite (python3 -m bench.bench).
# DATASET may list several (space-separated); empty = the embedded synthetic sequence plus
# ../shared/datasets/tum_fr1_rpy when present. Builds nothing: run `make setup` first.
set -euo pipefail
source "$(dirname "$0")/../common.sh"
help_on_request "$@"
cd "$ROOT"
ros_env
[ -x .ws/devel/lib/edge_slam_common/edge_slam_run ] || die "runner not built: run 'make setup' first"
[ -x .venv/bin/python ] || die "no .venv (evo, matplotlib): run 'make setup' first"
OUT="${OUT:-results/bench-$(date +%Y%m%d-%H%M)}"
ARGS=(--out "$OUT")
for d in ${DATASET:-}; do ARGS+=(--dataset "$d"); done
export PYTHONPATH="$ROOT/scripts${PYTHONPATH:+:$PYTHONPATH}"   # the bench package: python3 -m bench.<tool>
exec /usr/bin/python3 -m bench.bench "${ARGS[@]}" ${BENCH_ARGS:-}
