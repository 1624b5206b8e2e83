#include "edge_slam/module/keyframe_culling.h"

#include "edge_slam/data/map_edit.h"

#include <unordered_map>
#include <utility>

namespace edge_slam {

namespace {

// The keyframes a culling pass looks up, resolved once: each point's observers are mostly the
// same few dozen keyframes, and Map::keyframe takes the map's lock and copies a shared_ptr.
class KeyFrameLookup {
 public:
  explicit KeyFrameLookup(const Map& map) : map_(map) {}
  // Null when the keyframe is not in the map.
  const KeyFrame* find(uint32_t id) {
    auto it = cache_.find(id);
    if (it == cache_.end()) it = cache_.emplace(id, map_.keyframe(id)).first;
    return it->second.get();
  }

 private:
  const Map& map_;
  std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>> cache_;
};

bool redundant_with_lookup(const Map& map, const KeyFrame& kf, const KeyFrameCullingParams& params,
                           KeyFrameLookup& lookup) {
  const FrameFeatures& f = kf.features();
  const auto points = kf.map_points(map);
  std::vector<std::pair<uint32_t, int>> obs;  // reused: one point's observations, copied out of its lock
  int considered = 0, redundant = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& mp = points[i];
    if (!mp) continue;
    if (!f.is_close(i)) continue;  // RGB-D: only close points say what this keyframe adds
    ++considered;
    obs.clear();
    mp->for_each_observation([&obs](uint32_t id, int idx) { obs.emplace_back(id, idx); });
    // MapPoint::weighted_observations, from the same copy.
    int weighted = 0;
    for (const auto& [id, idx] : obs) weighted += observation_weight(lookup.find(id), idx);
    if (weighted <= params.min_other_observers) continue;
    const int level = f.keys_un[i].octave;
    int observers = 0;
    for (const auto& [other_id, idx] : obs) {
      if (other_id == kf.id()) continue;
      const KeyFrame* other = lookup.find(other_id);
      if (!other || other->is_bad() || idx < 0 || static_cast<size_t>(idx) >= other->features().size()) continue;
      if (other->features().keys_un[idx].octave <= level + 1 && ++observers >= params.min_other_observers) break;
    }
    if (observers >= params.min_other_observers) ++redundant;
  }
  return considered > 0 && redundant > params.redundant_ratio * considered;
}

}  // namespace

bool is_redundant_keyframe(const Map& map, const KeyFrame& kf, const KeyFrameCullingParams& params) {
  KeyFrameLookup lookup(map);
  return redundant_with_lookup(map, kf, params, lookup);
}

int cull_redundant_keyframes(Map& map, KeyFrameDatabase* database, const KeyFrame& kf,
                             const KeyFrameCullingParams& params, std::vector<std::shared_ptr<KeyFrame>>* culled_kfs) {
  int culled = 0;
  // One lookup for the whole pass: culling only marks keyframes bad (is_bad is read live).
  KeyFrameLookup lookup(map);
  for (uint32_t id : kf.ordered_neighbours()) {
    const auto other = map.keyframe(id);
    if (!other || other->is_bad() || other->parent_id() == kNoId || !other->loop_edges().empty()) continue;
    if (redundant_with_lookup(map, *other, params, lookup) && cull_keyframe(map, database, other)) {
      ++culled;
      if (culled_kfs) culled_kfs->push_back(other);
    }
  }
  return culled;
}

}  // namespace edge_slam
