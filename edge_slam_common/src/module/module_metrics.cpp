#include "edge_slam/module/module_metrics.h"

#include <string>

namespace edge_slam {

ModuleFigures collect_module_figures(const LocalMapping* mapping, const LoopClosing* loop) {
  ModuleFigures f;
  if (mapping) {
    f.has_mapping = true;
    f.mapping = mapping->stats();
    f.local_mapping_ms = mapping->process_times_ms();
    f.local_ba_ms = mapping->local_ba_times_ms();
  }
  if (loop) {
    f.has_loop_closing = true;
    f.loop_detection_ms = loop->detection_times_ms();
    f.loop_correction_ms = loop->correction_times_ms();
    f.loop_correction_locked_ms = loop->correction_locked_times_ms();
    f.loop_correction_longest_lock_ms = loop->correction_longest_lock_times_ms();
    f.full_ba_ms = loop->full_ba_times_ms();
    f.full_ba_runs = loop->full_ba_runs();
    f.loops_closed = loop->loops_closed();
    f.loops = loop->loops();
    // The essential graph's share of each correction (loops and merges), under the map lock.
    for (const auto& l : f.loops) f.loop_correction_graph_ms.push_back(l.correction.graph_ms);
    for (const auto& mg : loop->merges()) f.loop_correction_graph_ms.push_back(mg.correction.graph_ms);
  }
  return f;
}

void add_module_figures(MetricsJson& m, const ModuleFigures& f) {
  m.integer("loops_closed", f.loops_closed).integer("full_ba_runs", f.full_ba_runs);
  if (f.has_mapping) {
    const LocalMappingStats& s = f.mapping;
    MetricsJson stats;
    stats.integer("keyframes_processed", s.keyframes_processed)
        .integer("keyframes_skipped", s.keyframes_skipped)
        .integer("points_created", s.points_created)
        .integer("points_culled", s.points_culled)
        .integer("points_refuted", s.points_refuted)
        .integer("points_fused", s.points_fused)
        .integer("keyframes_culled", s.keyframes_culled)
        .integer("local_ba_runs", s.local_ba_runs)
        .integer("local_ba_aborted", s.local_ba_aborted)
        .integer("local_ba_failed", s.local_ba_failed)
        .integer("local_ba_free_keyframes", s.local_ba_free_keyframes)
        .integer("local_ba_fixed_keyframes", s.local_ba_fixed_keyframes)
        .integer("local_ba_observations", s.local_ba_observations)
        .integer("keyframes_mapped_beside_a_pause", s.keyframes_mapped_beside_a_pause);
    m.object("local_mapping", stats).timing("local_mapping_ms", f.local_mapping_ms).timing("local_ba_ms", f.local_ba_ms);
  }
  if (f.has_loop_closing) {
    m.timing("loop_detection_ms", f.loop_detection_ms)
        .timing("loop_correction_ms", f.loop_correction_ms)
        .timing("loop_correction_locked_ms", f.loop_correction_locked_ms)
        .timing("loop_correction_longest_lock_ms", f.loop_correction_longest_lock_ms)
        .timing("loop_correction_graph_ms", f.loop_correction_graph_ms)
        .timing("full_ba_ms", f.full_ba_ms);
    std::string loops = "[";
    for (size_t k = 0; k < f.loops.size(); ++k)
      loops += (k ? ", " : "") + std::string("{\"kf\": ") + std::to_string(f.loops[k].current_kf_id) +
               ", \"loop_kf\": " + std::to_string(f.loops[k].loop_kf_id) +
               ", \"matches\": " + std::to_string(f.loops[k].matches) + "}";
    m.raw("loops", loops + "]");
  }
}

}  // namespace edge_slam
