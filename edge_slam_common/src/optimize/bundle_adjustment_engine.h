// Private to src/optimize: the Ceres bundle adjustment both local and full BA are built on.
// A run is a sequence of passes; between passes outlier observations can be dropped.
#pragma once
#include <atomic>
#include <vector>

#include "edge_slam/optimize/bundle_adjustment_problem.h"

namespace edge_slam {
namespace optimize_detail {

struct BaPass {
  int iterations = 10;
  bool robust = true;  // Huber kernel on every residual
};

struct BaRunConfig {
  std::vector<BaPass> passes;
  bool drop_outliers_between_passes = false;
  bool fix_smallest_id_if_none_fixed = false;
  int num_threads = 1;
  std::atomic<bool>* abort = nullptr;
};

BundleAdjustmentResult run_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                             const BaRunConfig& config);

}  // namespace optimize_detail
}  // namespace edge_slam
