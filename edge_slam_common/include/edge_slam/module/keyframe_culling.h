// Redundant keyframe culling (ORB-SLAM2's KeyFrameCulling, RGB-D): a covisible keyframe of
// the new one is culled when more than 90% of its close-depth map points are seen by at
// least 3 other keyframes at the same or a finer pyramid level (+1). The map's root and
// keyframes with loop edges are kept; the spanning tree is repaired by cull_keyframe.
#pragma once
#include <vector>
#include <memory>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

struct KeyFrameCullingParams {
  double redundant_ratio = 0.9;
  int min_other_observers = 3;
};

// True when `kf`'s points are redundant by the rule above.
bool is_redundant_keyframe(const Map& map, const KeyFrame& kf, const KeyFrameCullingParams& params = {});

// Checks the covisible keyframes of `kf` and culls the redundant ones; returns how many and
// appends them to `culled` when given (each keeps its parent and T_cp: where it was, relative
// to the parent, when culled). The caller holds Map::update_mutex().
int cull_redundant_keyframes(Map& map, KeyFrameDatabase* database, const KeyFrame& kf,
                             const KeyFrameCullingParams& params = {},
                             std::vector<std::shared_ptr<KeyFrame>>* culled = nullptr);

}  // namespace edge_slam
