#include "edge_slam/optimize/local_bundle_adjustment.h"

#include "bundle_adjustment_engine.h"

namespace edge_slam {

BundleAdjustmentResult run_local_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                                   const LocalBaOptions& options) {
  optimize_detail::BaRunConfig config;
  config.passes = {{options.first_pass_iterations, true}, {options.second_pass_iterations, false}};
  config.drop_outliers_between_passes = true;
  config.num_threads = options.num_threads;
  config.abort = options.abort;
  return optimize_detail::run_bundle_adjustment(problem, config);
}

}  // namespace edge_slam
