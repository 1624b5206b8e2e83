# edge_slam front door. Every target is a thin wrapper around scripts/ so the same steps run
# by hand, from CI (.ci/run -> make test) and from the README.
#   make setup                       install Debian packages + venv, build, generate the default data
#   make demo  [HEADLESS=1]          setup, then run the main demo on the embedded synthetic sequence
#   make test                        setup, then every unit + integration test; ends "N passed, N failed"
#   make test-split                  only the split acceptance rostest (test/rostest/split_pipeline.test; also in make test)
#   make eval  DATASET=<TUM folder> MODE=monolithic|split|multi OUT=<dir> [EDGE_SLAM_ARGS="--camera X --vocabulary Y"]
#              (multi: several mobiles on one edge, scripts/eval_multi.sh; ROBOTS=2, ROBOT_DATASETS=... from the environment)
#   make bench [DATASET=<TUM folder or bag> ...] [OUT=<dir>]   benchmark suite -> OUT/report.md, bench.json
#   make fuzz  [FUZZ_SECONDS=60]     libFuzzer targets (clang, ASan+UBSan), each run FUZZ_SECONDS
#   make test-asan                   ASan+UBSan build: every unit test + one monolithic run
#   make dataset-multi               the default data plus a second robot in the same room (issue #16):
#                                    bags/synthetic_room_robot2/ + .bag (on demand only, not in setup)
SHELL := /bin/bash
DATASET ?= bags/synthetic_room
MODE ?= monolithic
OUT ?= results/$(notdir $(DATASET))-$(MODE)
HEADLESS ?= 0

.PHONY: setup demo test test-split eval bench dataset dataset-multi build
setup:
	bash scripts/setup.sh
build:
	bash scripts/build.sh
dataset:
	bash scripts/make_dataset.sh --force
# Both robots: robot 1 (the default, as setup makes it) and robot 2; each skipped when up to date.
dataset-multi:
	bash scripts/make_dataset.sh && bash scripts/make_dataset.sh --robot2
demo: setup
	HEADLESS=$(HEADLESS) bash scripts/demo.sh
test:
	bash scripts/test.sh
# The split acceptance run alone (ATE, updates, Local-Map bound, KeyFrame accounting, loop on the edge).
test-split:
	bash scripts/build.sh && export PATH=/usr/bin:$$PATH && source scripts/common.sh && ros_env && rostest test/rostest/split_pipeline.test repo:=$(CURDIR)
eval:
	DATASET="$(DATASET)" MODE="$(MODE)" OUT="$(OUT)" EDGE_SLAM_ARGS="$(EDGE_SLAM_ARGS)" bash scripts/eval.sh
# bench: DATASET/OUT only when given (the defaults above are for eval); BENCH_ARGS e.g. "--only monolithic,split".
bench:
	DATASET="$(if $(filter command line environment,$(origin DATASET)),$(DATASET))" \
	OUT="$(if $(filter command line environment,$(origin OUT)),$(OUT))" BENCH_ARGS="$(BENCH_ARGS)" \
	bash scripts/bench/bench.sh
.PHONY: fuzz test-asan
fuzz:
	FUZZ_SECONDS="$(or $(FUZZ_SECONDS),60)" bash scripts/fuzz.sh
test-asan:
	bash scripts/test_asan.sh
