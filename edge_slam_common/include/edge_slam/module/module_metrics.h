// The mapping part of metrics.json (Local-Mapping counters, per-call timings of local mapping,
// local BA, loop detection/correction and full BA, the loops closed), written the same way by
// the monolithic runner and the edge so evaluation and benchmarks read both alike.
#pragma once
#include <vector>

#include "edge_slam/io/metrics_json.h"
#include "edge_slam/module/local_mapping.h"
#include "edge_slam/module/loop_closing.h"

namespace edge_slam {

struct ModuleFigures {
  bool has_mapping = false, has_loop_closing = false;
  LocalMappingStats mapping;
  std::vector<double> local_mapping_ms, local_ba_ms, loop_detection_ms, loop_correction_ms, full_ba_ms;
  std::vector<double> loop_correction_locked_ms;  // the part of each correction under the map lock
  std::vector<double> loop_correction_longest_lock_ms;  // ... its longest hold (several robots: two holds)
  std::vector<double> loop_correction_graph_ms;   // of which the essential graph
  int full_ba_runs = 0, loops_closed = 0;
  std::vector<LoopEvent> loops;
};

// Copies the figures out of the modules (either may be null: not running).
ModuleFigures collect_module_figures(const LocalMapping* mapping, const LoopClosing* loop);

// loops_closed and full_ba_runs always; local_mapping{...} and its timings when mapping ran;
// the loop timings and loops[] when loop closing ran.
void add_module_figures(MetricsJson& m, const ModuleFigures& f);

}  // namespace edge_slam
