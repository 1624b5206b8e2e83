#include "edge_slam/module/local_mapping_params.h"

namespace edge_slam {

LocalMappingParams load_local_mapping_params(const ConfigMap& cfg) {
  LocalMappingParams p;
  MapPointCullingParams& c = p.point_culling;
  c.min_found_ratio = static_cast<float>(
      cfg.get_double_or("local_mapping/point_min_found_ratio", c.min_found_ratio, 0.0, 1.0));
  c.min_observers = cfg.get_int_or("local_mapping/point_min_observers", c.min_observers, 0, 1000);
  c.probation_keyframes = static_cast<uint32_t>(
      cfg.get_int_or("local_mapping/point_probation_keyframes", static_cast<int>(c.probation_keyframes), 0, 1000));
  p.triangulation.num_covisibles = static_cast<size_t>(cfg.get_int_or(
      "local_mapping/triangulation_covisibles", static_cast<int>(p.triangulation.num_covisibles), 1, 1000));
  p.local_ba = cfg.get_bool_or("local_mapping/local_ba", p.local_ba);
  p.ba_first_pass_iterations =
      cfg.get_int_or("local_mapping/ba_first_pass_iterations", p.ba_first_pass_iterations, 1, 1000);
  p.ba_second_pass_iterations =
      cfg.get_int_or("local_mapping/ba_second_pass_iterations", p.ba_second_pass_iterations, 0, 1000);
  p.ba_num_threads = cfg.get_int_or("local_mapping/ba_num_threads", p.ba_num_threads, 1, 64);
  p.ba_window.max_free_keyframes = static_cast<size_t>(cfg.get_int_or(
      "local_mapping/ba_max_free_keyframes", static_cast<int>(p.ba_window.max_free_keyframes), 0, 100000));
  p.ba_window.max_fixed_keyframes = static_cast<size_t>(cfg.get_int_or(
      "local_mapping/ba_max_fixed_keyframes", static_cast<int>(p.ba_window.max_fixed_keyframes), 0, 100000));
  p.cull_keyframes = cfg.get_bool_or("local_mapping/cull_keyframes", p.cull_keyframes);
  KeyFrameCullingParams& k = p.keyframe_culling;
  k.redundant_ratio = cfg.get_double_or("local_mapping/keyframe_redundant_ratio", k.redundant_ratio, 0.0, 1.0);
  k.min_other_observers =
      cfg.get_int_or("local_mapping/keyframe_min_other_observers", k.min_other_observers, 1, 1000);
  return p;
}

}  // namespace edge_slam
