#include "edge_slam/optimize/full_bundle_adjustment.h"

#include "bundle_adjustment_engine.h"

namespace edge_slam {

BundleAdjustmentResult run_full_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                                  int iterations, std::atomic<bool>* abort,
                                                  int num_threads) {
  optimize_detail::BaRunConfig config;
  config.passes = {{iterations, true}};
  config.fix_smallest_id_if_none_fixed = true;
  config.num_threads = num_threads;
  config.abort = abort;
  return optimize_detail::run_bundle_adjustment(problem, config);
}

}  // namespace edge_slam
