// Copies a part of the Map into a BundleAdjustmentProblem and writes a result back, for the
// local BA after each keyframe and the full BA after a loop closure. Building and applying
// need Map::update_mutex() held by the caller; the solve in between does not.
#pragma once
#include <memory>
#include <unordered_set>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/optimize/bundle_adjustment_problem.h"

namespace edge_slam {

// Local window of `kf` (ORB-SLAM2's LocalBundleAdjustment): kf and all its covisible
// keyframes are free (the map's root stays fixed), their points are adjusted, and the other
// keyframes observing those points are included fixed. Empty problem when kf is bad.
BundleAdjustmentProblem build_local_ba_problem(const Map& map, const KeyFrame& kf);

// Every good keyframe (the root fixed) and point of the map.
BundleAdjustmentProblem build_full_ba_problem(const Map& map);

struct BaApplyStats {
  int keyframes = 0, points = 0, erased_observations = 0;
};

// Writes poses of free keyframes and positions of points that are still good, refreshes the
// points' normals, and (erase_outliers) unlinks observations reported as outliers.
BaApplyStats apply_ba_result(Map& map, const BundleAdjustmentProblem& problem,
                             const BundleAdjustmentResult& result, bool erase_outliers);

}  // namespace edge_slam
