#include "edge_slam/optimize/pose_optimizer.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "pose_batch_cost.h"
#include "pose_parameters.h"
#include "reprojection_cost.h"

namespace edge_slam {

using optimize_detail::PixelMeasurement;
using optimize_detail::PoseParameters;

namespace {

PixelMeasurement to_measurement(const PoseObservation& o) {
  return PixelMeasurement{o.pixel, o.right_x, o.inv_sigma2};
}

bool is_usable(const PoseObservation& o) {
  return o.point_world.allFinite() && o.pixel.allFinite() && std::isfinite(o.right_x) &&
         std::isfinite(o.inv_sigma2) && o.inv_sigma2 > 0.0;
}

PoseOptimizationResult failure(const std::string& why) {
  PoseOptimizationResult r;
  r.ok = false;
  r.message = why;
  return r;
}

bool is_outlier_at(const PinholeCamera& cam, const PoseObservation& o, const Eigen::Quaterniond& q,
                   const Eigen::Vector3d& t) {
  const PixelMeasurement m = to_measurement(o);
  return optimize_detail::is_reprojection_outlier(optimize_detail::evaluate_reprojection(cam, m, q, t, o.point_world), m);
}

}  // namespace

PoseOptimizationResult optimize_pose(const PinholeCamera& cam,
                                     const std::vector<PoseObservation>& obs,
                                     Eigen::Isometry3d& T_cw, std::vector<bool>& is_outlier,
                                     const PoseOptimizationOptions& options) {
  if (!optimize_detail::is_finite_isometry(T_cw)) return failure("initial pose is not finite");

  std::vector<bool> usable(obs.size());
  int num_usable = 0;
  for (size_t i = 0; i < obs.size(); ++i) {
    usable[i] = is_usable(obs[i]);
    num_usable += usable[i] ? 1 : 0;
  }
  if (num_usable < options.min_observations) {
    return failure("too few usable observations: " + std::to_string(num_usable));
  }

  std::vector<bool> outlier(obs.size(), false);
  for (size_t i = 0; i < obs.size(); ++i) {
    outlier[i] = !usable[i] || (i < is_outlier.size() && is_outlier[i]);
  }

  PoseParameters pose = PoseParameters::from_isometry(T_cw);

  // One problem for all rounds: every usable observation in one hand-written residual block
  // (pose_batch_cost.h: the per-observation Huber cost, at a fraction of Ceres' per-block
  // overhead); a round switches observations on and off and the kernel on or off.
  std::vector<size_t> slot_of(obs.size(), 0);  // observation -> index in the batch
  std::vector<PixelMeasurement> measurements;
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < obs.size(); ++i) {
    if (!usable[i]) continue;
    slot_of[i] = measurements.size();
    measurements.push_back(to_measurement(obs[i]));
    points.push_back(obs[i].point_world);
  }
  optimize_detail::PoseBatchCost batch(cam, measurements, points);
  optimize_detail::PairedCostLoss batch_loss(batch);
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  problem.AddParameterBlock(pose.q, 4, &quaternion_manifold);
  problem.AddParameterBlock(pose.t, 3);
  problem.AddResidualBlock(&batch, &batch_loss, pose.q, pose.t);

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // 6 unknowns
  solver_options.max_num_iterations = options.iterations_per_round;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.num_threads = 1;

  const int rounds = std::max(1, options.rounds);
  for (int round = 0; round < rounds; ++round) {
    batch.set_robust(round + 1 < rounds);  // last round: plain least squares
    int num_residuals = 0;
    for (size_t i = 0; i < obs.size(); ++i) {
      if (!usable[i]) continue;
      // A point behind the camera cannot be evaluated by the residual: it sits out this round.
      // (After round 0 the classification below already flagged those: checked once.)
      if (round == 0 && !outlier[i] && optimize_detail::evaluate_reprojection(cam, measurements[slot_of[i]], pose.quaternion(),
                                                                pose.translation(), obs[i].point_world)
                                 .depth <= optimize_detail::kMinDepth)
        outlier[i] = true;
      batch.set_active(slot_of[i], !outlier[i]);
      num_residuals += outlier[i] ? 0 : 1;
    }
    if (num_residuals < options.min_observations) {
      if (round == 0) return failure("too few observations in front of the camera");
      break;  // keep the pose of the previous round
    }

    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    if (!summary.IsSolutionUsable() || !pose.is_finite()) {
      return failure("ceres failed: " + summary.message);
    }

    const Eigen::Quaterniond q = pose.quaternion();  // normalised once, not per observation
    const Eigen::Vector3d t = pose.translation();
    for (size_t i = 0; i < obs.size(); ++i) {
      outlier[i] = !usable[i] || is_outlier_at(cam, obs[i], q, t);
    }
  }

  PoseOptimizationResult result;
  result.ok = true;
  for (size_t i = 0; i < obs.size(); ++i) result.inliers += outlier[i] ? 0 : 1;
  result.message = "inliers " + std::to_string(result.inliers) + "/" + std::to_string(obs.size());
  T_cw = pose.to_isometry();
  is_outlier = outlier;
  return result;
}

}  // namespace edge_slam
