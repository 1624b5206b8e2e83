#include "edge_slam/module/map_point_culling.h"

#include "edge_slam/data/map_edit.h"
#include "edge_slam/util/robot_ids.h"

namespace edge_slam {

bool on_probation(uint32_t made_by, uint32_t current, const MapPointCullingParams& params) {
  const int robot = robot_of_keyframe(made_by);
  if (robot < 0 || robot != robot_of_keyframe(current) || current <= made_by) return false;
  return current - made_by <= params.probation_keyframes;
}

std::vector<uint32_t> refute_unfound_points(Map& map, uint32_t new_kf_id, const MapPointCullingParams& params) {
  std::vector<uint32_t> refuted;
  for (const auto& mp : map.map_points()) {
    if (!mp || mp->is_bad() || !on_probation(mp->reference_kf_id(), new_kf_id, params)) continue;
    if (!found_too_rarely(*mp, params)) continue;
    refuted.push_back(mp->id());
    erase_map_point(map, mp);
  }
  return refuted;
}

int RecentMapPoints::cull(Map& map, uint32_t current_kf_id, const std::unordered_set<uint32_t>* refuted,
                          int* num_refuted) {
  int erased = 0;
  const int robot = robot_of_keyframe(current_kf_id);
  if (robot < 0) return 0;
  if (newest_by_robot_.size() <= static_cast<size_t>(robot)) newest_by_robot_.resize(robot + 1, 0);
  newest_by_robot_[robot] = std::max(newest_by_robot_[robot], current_kf_id);
  for (auto it = points_.begin(); it != points_.end();) {
    const auto mp = map.map_point(it->first);
    const int maker = robot_of_keyframe(it->second);
    const uint32_t newest = maker >= 0 && static_cast<size_t>(maker) < newest_by_robot_.size()
                                ? newest_by_robot_[maker] : it->second;
    const uint32_t age = newest >= it->second ? newest - it->second : 0;
    bool drop_from_list = true;
    if (!mp || mp->is_bad()) {
      // already gone
    } else if (refuted && refuted->count(it->first)) {
      erase_map_point(map, mp);
      ++erased;
      if (num_refuted) ++*num_refuted;
    } else if (found_too_rarely(*mp, params_) ||
               (age >= 2 && mp->weighted_observations(map) < params_.min_observers)) {
      erase_map_point(map, mp);
      ++erased;
    } else if (age < params_.probation_keyframes) {
      drop_from_list = false;
    }
    it = drop_from_list ? points_.erase(it) : std::next(it);
  }
  return erased;
}

}  // namespace edge_slam
