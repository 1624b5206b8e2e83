#include "edge_slam/module/map_point_culling.h"

#include "edge_slam/data/map_edit.h"

namespace edge_slam {

int RecentMapPoints::cull(Map& map, uint32_t current_kf_id) {
  int erased = 0;
  for (auto it = points_.begin(); it != points_.end();) {
    const auto mp = map.map_point(it->first);
    const uint32_t age = current_kf_id >= it->second ? current_kf_id - it->second : 0;
    bool drop_from_list = true;
    if (!mp || mp->is_bad()) {
      // already gone
    } else if (mp->found_ratio() < params_.min_found_ratio ||
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
