"""The benchmark and evaluation tools as one package (run from scripts/ as `python3 -m bench.<tool>`,
scripts/bench/bench.sh and scripts/eval.sh set PYTHONPATH).

Layers, each importing only those above it:
  bench_data      readers of one run's files (JSON, CSV, /proc samples, topic sizes)
  pipeline_stats  map-update pipeline figures from the per-event CSVs
  ate             evo: ATE, trajectory alignment, the largest jump at an update
  ros_util        rospy/rosservice helpers; netns: network namespaces (also test/delivery)
  report          OUT/runs -> report.md / bench.json; bench: the orchestrator
The TUM text reader is edge_slam_common's (edge_slam_common/python/edge_slam_common/tum.py).
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
_TUM = os.path.join(ROOT, "edge_slam_common", "python")
if _TUM not in sys.path:
    sys.path.insert(0, _TUM)
