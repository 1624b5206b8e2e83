// Applies a full BA result computed on a snapshot of the map while the map kept growing
// (ORB-SLAM2's RunGlobalBundleAdjustment update): keyframes in the snapshot take their
// adjusted pose, keyframes created meanwhile follow their spanning-tree parent (their pose
// relative to it is kept), points in the snapshot take their adjusted position and newer
// points follow their reference keyframe. The caller holds Map::update_mutex() with local
// mapping paused. Returns the number of keyframes moved by propagation.
#pragma once
#include "edge_slam/data/map.h"
#include "edge_slam/optimize/bundle_adjustment_problem.h"

namespace edge_slam {

int apply_full_ba_result(Map& map, const BundleAdjustmentResult& result);

}  // namespace edge_slam
