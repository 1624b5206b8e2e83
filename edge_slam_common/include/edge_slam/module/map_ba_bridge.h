// Copies a part of the Map into a BundleAdjustmentProblem and writes a result back, for the
// local BA after each keyframe and the full BA after a loop closure. Building and applying
// need Map::update_mutex() held by the caller; the solve in between does not.
#pragma once
#include <functional>
#include <cstddef>
#include <memory>
#include <unordered_set>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/optimize/bundle_adjustment_problem.h"

namespace edge_slam {

// Bounds on the local window; 0 = unbounded, ORB-SLAM2's and the paper's window.
struct LocalBaWindow {
  // kf plus at most this many - 1 covisible keyframes, the strongest covisibility first.
  size_t max_free_keyframes = 0;
  // At most this many fixed keyframes, those observing the most window points first; the
  // observations of the others are left out.
  size_t max_fixed_keyframes = 0;
};

// Local window of `kf` (ORB-SLAM2's LocalBundleAdjustment): kf and its covisible keyframes
// are free (the map's root stays fixed), their points are adjusted, and the other keyframes
// observing those points are included fixed, both within `window`. Empty problem when kf is bad.
// Why bounds: when the camera stays in one place (fr1_rpy turns on the spot) every keyframe is
// covisible with every other, the unbounded window is the whole map and its cost grows with it.
BundleAdjustmentProblem build_local_ba_problem(const Map& map, const KeyFrame& kf,
                                               const LocalBaWindow& window = {});

// Every good keyframe (the root fixed) and point of the map.
// in_map: the KeyFrames to adjust (unset: all), e.g. one robot's map of several; points enter
// with their observations in those KeyFrames (none: left out).
BundleAdjustmentProblem build_full_ba_problem(const Map& map, const std::function<bool(uint32_t kf_id)>& in_map = {});

struct BaApplyStats {
  int keyframes = 0, points = 0, erased_observations = 0;
};

// Writes poses of free keyframes and positions of points that are still good, refreshes the
// points' normals, and (erase_outliers) unlinks observations reported as outliers.
BaApplyStats apply_ba_result(Map& map, const BundleAdjustmentProblem& problem,
                             const BundleAdjustmentResult& result, bool erase_outliers);

}  // namespace edge_slam
