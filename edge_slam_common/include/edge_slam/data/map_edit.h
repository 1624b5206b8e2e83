// Map edits that touch several objects at once and must leave them consistent: erasing a
// map point, dropping one observation, replacing a duplicate point by another (fusion) and
// culling a keyframe (spanning tree repaired). Callers changing the map as a whole hold
// Map::update_mutex(); these functions only take the per-object locks.
#pragma once
#include <memory>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/map_point.h"

namespace edge_slam {

class KeyFrameDatabase;

// Marks the point bad, unlinks it from every observing keyframe and removes it from the map.
void erase_map_point(Map& map, const std::shared_ptr<MapPoint>& mp);

// Links keypoint `index` of `kf` and `mp` both ways.
void add_observation(const std::shared_ptr<KeyFrame>& kf, size_t index, const std::shared_ptr<MapPoint>& mp);

// Unlinks `mp` from `kf` (both ways); a point left without observations is erased.
void erase_observation(Map& map, const std::shared_ptr<KeyFrame>& kf, const std::shared_ptr<MapPoint>& mp);

// Moves every observation of `old_mp` to `by` (a keyframe already observing `by` just loses
// its `old_mp` keypoint link), adds up the tracking statistics, marks `old_mp` bad with
// replaced_by = by, erases it from the map and refreshes `by`'s descriptor.
void replace_map_point(Map& map, const std::shared_ptr<MapPoint>& old_mp, const std::shared_ptr<MapPoint>& by);

// Keyframe culling: drops its covisibility edges and observations, re-attaches each child to
// the candidate parent (its former parent or an already re-attached sibling) it shares most
// points with, remembers its pose relative to its parent, erases it from the map and the
// database (may be null). Does nothing to a keyframe without a parent (the map's root).
// Returns false when nothing was done.
bool cull_keyframe(Map& map, KeyFrameDatabase* database, const std::shared_ptr<KeyFrame>& kf);

}  // namespace edge_slam
