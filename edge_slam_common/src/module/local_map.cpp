#include "edge_slam/module/local_map.h"

#include <unordered_map>
#include <unordered_set>

#include "edge_slam/util/flat_id_set.h"

namespace edge_slam {

LocalMap build_local_map(const Frame& frame, const Map& map, size_t max_keyframes,
                         size_t neighbours_per_keyframe) {
  LocalMap local;
  // 1. Keyframes observing the frame's matched points, with the number of shared points.
  std::unordered_map<uint32_t, int> shared;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp || mp->is_bad() || frame.outliers[i]) continue;
    mp->for_each_observation([&](uint32_t kf_id, int) { ++shared[kf_id]; });
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
  // 3. Their map points, each once, in keyframe then keypoint order. The ids are deduplicated
  // first and only the survivors resolved, in one pass under the map's lock: in a local map of
  // 25 keyframes (~25,000 ids) only ~16,000 are distinct. A point that is absent or bad is so
  // under every id reference to it, so dropping it after deduplication keeps the same list.
  std::vector<uint32_t> ids;
  FlatIdSet seen;
  seen.reserve(local.keyframes.size() * 1000);
  for (const auto& kf : local.keyframes)
    for (uint32_t id : kf->map_point_ids())
      if (seen.insert(id)) ids.push_back(id);
  local.points.reserve(ids.size());
  for (auto& mp : map.map_points(ids))
    if (mp && !mp->is_bad()) local.points.push_back(std::move(mp));
  return local;
}

}  // namespace edge_slam
