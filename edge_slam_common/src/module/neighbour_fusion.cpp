#include "edge_slam/module/neighbour_fusion.h"

#include <unordered_set>

#include "edge_slam/match/keyframe_search.h"

namespace edge_slam {

int fuse_with_neighbours(Map& map, const std::shared_ptr<KeyFrame>& kf, size_t num_neighbours,
                         size_t num_second_neighbours) {
  if (kf->is_bad()) return 0;
  std::vector<std::shared_ptr<KeyFrame>> targets;
  std::unordered_set<uint32_t> seen{kf->id()};
  auto try_add = [&](uint32_t id) {
    if (!seen.insert(id).second) return;
    auto t = map.keyframe(id);
    if (t && !t->is_bad()) targets.push_back(std::move(t));
  };
  for (uint32_t id : kf->best_covisibles(num_neighbours)) try_add(id);
  const size_t first_ring = targets.size();
  for (size_t i = 0; i < first_ring; ++i)
    for (uint32_t id : targets[i]->best_covisibles(num_second_neighbours)) try_add(id);

  FuseOptions options;
  int fused = 0;
  for (const auto& t : targets) {
    std::vector<std::shared_ptr<MapPoint>> mine;
    for (auto& mp : kf->map_points(map))
      if (mp) mine.push_back(std::move(mp));
    fused += fuse(map, t, t->T_cw(), mine, options);
  }
  std::vector<std::shared_ptr<MapPoint>> theirs;
  std::unordered_set<uint32_t> taken;
  for (const auto& t : targets)
    for (auto& mp : t->map_points(map))
      if (mp && taken.insert(mp->id()).second) theirs.push_back(std::move(mp));
  fused += fuse(map, kf, kf->T_cw(), theirs, options);

  for (const auto& mp : kf->map_points(map)) {
    if (!mp) continue;
    mp->update_descriptor(map);
    mp->update_normal_and_depth(map);
  }
  kf->update_connections(map);
  return fused;
}

}  // namespace edge_slam
