// Full (global) bundle adjustment, run after a loop closure: every keyframe and point, Huber
// kernels throughout and no outlier removal pass (as ORB-SLAM2's GlobalBundleAdjustment).
#pragma once
#include <atomic>

#include "edge_slam/optimize/bundle_adjustment_problem.h"

namespace edge_slam {

// Keyframes flagged fixed stay fixed; when none is flagged, the keyframe with the smallest id is
// held fixed to remove the gauge freedom. outlier_observations is informative only (chi2 test at
// the end). abort may be null; see LocalBaOptions::abort for its semantics.
BundleAdjustmentResult run_full_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                                  int iterations,
                                                  std::atomic<bool>* abort = nullptr,
                                                  int num_threads = 1);

}  // namespace edge_slam
