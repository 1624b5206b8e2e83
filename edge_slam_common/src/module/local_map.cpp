#include "edge_slam/module/local_map.h"

#include <unordered_map>
#include <unordered_set>

namespace edge_slam {

LocalMap build_local_map(const Frame& frame, const Map& map, size_t max_keyframes,
                         size_t neighbours_per_keyframe) {
  LocalMap local;
  // 1. Keyframes observing the frame's matched points, with the number of shared points.
  std::unordered_map<uint32_t, int> shared;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp || mp->is_bad() || frame.outliers[i]) continue;
    for (const auto& obs : mp->observations()) ++shared[obs.first];
  }
  std::unordered_set<uint32_t> included;
  int best = 0;
  for (const auto& [kf_id, n] : shared) {
    auto kf = map.keyframe(kf_id);
    if (!kf || kf->is_bad()) continue;
    if (n > best) {
      best = n;
      local.reference = kf;
    }
    included.insert(kf_id);
    local.keyframes.push_back(std::move(kf));
  }
  // 2. Extend each with one new strong covisible neighbour, child and parent.
  auto try_add = [&](uint32_t id) {
    if (local.keyframes.size() >= max_keyframes || included.count(id)) return false;
    auto kf = map.keyframe(id);
    if (!kf || kf->is_bad()) return false;
    included.insert(id);
    local.keyframes.push_back(std::move(kf));
    return true;
  };
  const size_t first_ring = local.keyframes.size();
  for (size_t k = 0; k < first_ring && local.keyframes.size() < max_keyframes; ++k) {
    const auto kf = local.keyframes[k];
    for (uint32_t nb : kf->best_covisibles(neighbours_per_keyframe))
      if (try_add(nb)) break;
    for (uint32_t child : kf->children())
      if (try_add(child)) break;
    if (kf->parent_id() != kNoId) try_add(kf->parent_id());
  }
  // 3. Their map points, each once.
  std::unordered_set<uint32_t> seen;
  for (const auto& kf : local.keyframes)
    for (auto& mp : kf->map_points(map))
      if (mp && seen.insert(mp->id()).second) local.points.push_back(std::move(mp));
  return local;
}

}  // namespace edge_slam
