#pragma once
// Where the points the last frame tracked went in a Local-Map update. The edge fuses duplicate
// points (local mapping's fusion, a loop correction's): the survivor keeps its id, the other
// one's observations move to it. An update carries the survivor only, so the mobile, relinking
// its last frame by id, lost every fused point it was tracking: 10-30% of the last frame's
// points at fr1's first update (2026-12-05), after which the next frame had about half the
// matches. ORB-SLAM2's tracking follows the replacement (MapPoint::GetReplaced). The update
// says it without a field of its own: a point the mobile saw at keypoint i of KeyFrame K is,
// when the update holds K, whatever point K's keypoint i observes now. A point the edge culled
// leaves that keypoint empty, and stays lost.
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "edge_slam/data/map.h"

namespace edge_slam {

// A point and the (KeyFrame id, keypoint index) pairs it was observed at before the update.
struct PointSightings {
  uint32_t point_id = 0;
  std::vector<std::pair<uint32_t, int>> observed_at;
};

// Old id -> the id of the point now at one of its sightings, for each point `map` no longer
// holds by its own id; sightings in KeyFrames `map` does not hold say nothing. Takes no lock:
// call it with the map's update mutex held or while nothing else edits the map.
std::unordered_map<uint32_t, uint32_t> find_point_replacements(const Map& map,
                                                               const std::vector<PointSightings>& before);

}  // namespace edge_slam
