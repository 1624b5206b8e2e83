#include "edge_slam/module/point_replacements.h"

namespace edge_slam {

std::unordered_map<uint32_t, uint32_t> find_point_replacements(const Map& map,
                                                               const std::vector<PointSightings>& before) {
  std::unordered_map<uint32_t, uint32_t> replaced;
  for (const PointSightings& s : before) {
    if (map.map_point(s.point_id)) continue;  // still there: nothing to follow
    for (const auto& [kf_id, index] : s.observed_at) {
      const auto kf = map.keyframe(kf_id);
      if (!kf || index < 0) continue;  // map_point_id is kNoId past the keypoints
      const uint32_t now = kf->map_point_id(static_cast<size_t>(index));
      if (now == kNoId || now == s.point_id || !map.map_point(now)) continue;
      replaced.emplace(s.point_id, now);
      break;
    }
  }
  return replaced;
}

}  // namespace edge_slam
