// Local bundle adjustment after each new keyframe, following ORB-SLAM2's LocalBundleAdjustment:
// pass 1 with Huber kernels (delta sqrt(5.991) mono, sqrt(7.815) stereo); observations whose
// chi2 then exceeds the threshold, or whose point lies behind the camera, are dropped; pass 2
// refines without them and without the robust kernel. The final outliers are reported so the
// caller can erase those map-point associations.
#pragma once
#include <atomic>

#include "edge_slam/optimize/bundle_adjustment_problem.h"

namespace edge_slam {

struct LocalBaOptions {
  int first_pass_iterations = 5;
  int second_pass_iterations = 10;
  int num_threads = 1;
  // Polled after every iteration; when it reads true the solver stops (keeping its progress),
  // pass 2 is skipped and result.aborted is set. Used when a new keyframe arrives.
  std::atomic<bool>* abort = nullptr;
};

// ok=false with a message when no keyframe is free, no usable observation remains, ids are
// duplicated, a keyframe pose is non-finite, or Ceres fails.
BundleAdjustmentResult run_local_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                                   const LocalBaOptions& options = {});

}  // namespace edge_slam
