#include "edge_slam/module/keyframe_culling.h"

#include "edge_slam/data/map_edit.h"

namespace edge_slam {

bool is_redundant_keyframe(const Map& map, const KeyFrame& kf, const KeyFrameCullingParams& params) {
  const FrameFeatures& f = kf.features();
  const auto points = kf.map_points(map);
  int considered = 0, redundant = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& mp = points[i];
    if (!mp) continue;
    if (!f.is_close(i)) continue;  // RGB-D: only close points say what this keyframe adds
    ++considered;
    const auto obs = mp->observations();
    if (mp->weighted_observations(map) <= params.min_other_observers) continue;
    const int level = f.keys_un[i].octave;
    int observers = 0;
    for (const auto& [other_id, idx] : obs) {
      if (other_id == kf.id()) continue;
      const auto other = map.keyframe(other_id);
      if (!other || other->is_bad() || idx < 0 || static_cast<size_t>(idx) >= other->features().size()) continue;
      if (other->features().keys_un[idx].octave <= level + 1 && ++observers >= params.min_other_observers) break;
    }
    if (observers >= params.min_other_observers) ++redundant;
  }
  return considered > 0 && redundant > params.redundant_ratio * considered;
}

int cull_redundant_keyframes(Map& map, KeyFrameDatabase* database, const KeyFrame& kf,
                             const KeyFrameCullingParams& params, std::vector<std::shared_ptr<KeyFrame>>* culled_kfs) {
  int culled = 0;
  for (uint32_t id : kf.ordered_neighbours()) {
    const auto other = map.keyframe(id);
    if (!other || other->is_bad() || other->parent_id() == kNoId || !other->loop_edges().empty()) continue;
    if (is_redundant_keyframe(map, *other, params) && cull_keyframe(map, database, other)) {
      ++culled;
      if (culled_kfs) culled_kfs->push_back(other);
    }
  }
  return culled;
}

}  // namespace edge_slam
