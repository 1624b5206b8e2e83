// The tracker's local map: keyframes that observe the frame's matched points, plus their
// strongest covisible neighbours and spanning-tree relatives (capped), and the map
// points those keyframes see.
#pragma once
#include <memory>
#include <vector>

#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

struct LocalMap {
  std::vector<std::shared_ptr<KeyFrame>> keyframes;
  std::vector<std::shared_ptr<MapPoint>> points;
  std::shared_ptr<KeyFrame> reference;  // keyframe sharing most points with the frame
};

// max_keyframes: ORB-SLAM2 caps the local keyframes at 80; neighbours per keyframe: 10.
LocalMap build_local_map(const Frame& frame, const Map& map, size_t max_keyframes = 80,
                         size_t neighbours_per_keyframe = 10);

}  // namespace edge_slam
