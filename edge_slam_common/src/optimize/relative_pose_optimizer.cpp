#include "edge_slam/optimize/relative_pose_optimizer.h"

#include <ceres/ceres.h>

#include <cmath>
#include <limits>
#include <memory>

#include "pose_parameters.h"
#include "reprojection_cost.h"

namespace edge_slam {

using optimize_detail::PoseParameters;

namespace {

bool is_usable(const RelativePoseMatch& m) {
  return m.point_in_1.allFinite() && m.pixel_in_1.allFinite() && m.point_in_2.allFinite() &&
         m.pixel_in_2.allFinite() && std::isfinite(m.inv_sigma2_1) && m.inv_sigma2_1 > 0.0 &&
         std::isfinite(m.inv_sigma2_2) && m.inv_sigma2_2 > 0.0 && std::isfinite(m.right_x_1) &&
         std::isfinite(m.right_x_2);
}

optimize_detail::PixelMeasurement measurement_in_1(const RelativePoseMatch& m) {
  return {m.pixel_in_1, m.right_x_1, m.inv_sigma2_1};
}
optimize_detail::PixelMeasurement measurement_in_2(const RelativePoseMatch& m) {
  return {m.pixel_in_2, m.right_x_2, m.inv_sigma2_2};
}

// Chi2 of a term; infinite when the point is not in front of the observing camera.
double term_chi2(const PinholeCamera& cam, const Eigen::Vector3d& p_cam, const optimize_detail::PixelMeasurement& m) {
  const auto check = optimize_detail::evaluate_reprojection(cam, m, Eigen::Quaterniond::Identity(),
                                                            Eigen::Vector3d::Zero(), p_cam);
  return check.depth > optimize_detail::kMinDepth ? check.chi2 : std::numeric_limits<double>::infinity();
}

// The threshold given for a monocular term, scaled to a stereo-projected term's degrees of freedom.
double stereo_threshold(double mono_threshold) {
  return mono_threshold * optimize_detail::kChi2Stereo / optimize_detail::kChi2Mono;
}
double term_threshold(const optimize_detail::PixelMeasurement& m, double mono_threshold) {
  return m.is_stereo() ? stereo_threshold(mono_threshold) : mono_threshold;
}

bool match_is_inlier(const PinholeCamera& cam, const RelativePoseMatch& m, const Eigen::Isometry3d& T_12,
                     double threshold) {
  const auto m1 = measurement_in_1(m), m2 = measurement_in_2(m);
  return term_chi2(cam, T_12 * m.point_in_2, m1) <= term_threshold(m1, threshold) &&
         term_chi2(cam, T_12.inverse() * m.point_in_1, m2) <= term_threshold(m2, threshold);
}

RelativePoseResult failure(const Eigen::Isometry3d& T_12, size_t n, const std::string& why) {
  RelativePoseResult r;
  r.T_12 = T_12;
  r.inliers.assign(n, false);
  r.message = why;
  return r;
}

}  // namespace

RelativePoseResult optimize_relative_pose(const PinholeCamera& cam,
                                          const std::vector<RelativePoseMatch>& matches,
                                          const Eigen::Isometry3d& T_12_initial,
                                          const RelativePoseOptions& options) {
  const size_t n = matches.size();
  if (!optimize_detail::is_finite_isometry(T_12_initial)) return failure(T_12_initial, n, "initial transform is not finite");
  std::vector<bool> active(n);
  int num_usable = 0;
  for (size_t i = 0; i < n; ++i) {
    active[i] = is_usable(matches[i]);
    num_usable += active[i] ? 1 : 0;
  }
  if (num_usable < options.min_matches) {
    return failure(T_12_initial, n, "too few usable matches: " + std::to_string(num_usable));
  }

  // Two terms per match: [2i] keyframe 2's point seen in keyframe 1, [2i+1] the converse.
  std::vector<std::unique_ptr<ceres::CostFunction>> costs(2 * n);
  for (size_t i = 0; i < n; ++i) {
    if (!active[i]) continue;
    const RelativePoseMatch& m = matches[i];
    costs[2 * i].reset(optimize_detail::make_pose_only_reprojection_cost(cam, measurement_in_1(m), m.point_in_2));
    costs[2 * i + 1].reset(optimize_detail::make_inverse_pose_reprojection_cost(cam, measurement_in_2(m), m.point_in_1));
  }
  ceres::HuberLoss huber_mono(std::sqrt(options.chi2_threshold));
  ceres::HuberLoss huber_stereo(std::sqrt(stereo_threshold(options.chi2_threshold)));
  auto huber = [&](const optimize_detail::PixelMeasurement& m) -> ceres::LossFunction* {
    return m.is_stereo() ? &huber_stereo : &huber_mono;
  };
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.num_threads = 1;

  PoseParameters pose = PoseParameters::from_isometry(T_12_initial);
  const int pass_iterations[2] = {options.first_pass_iterations, options.second_pass_iterations};
  for (int pass = 0; pass < 2; ++pass) {
    const bool robust = pass == 0;
    const Eigen::Isometry3d current = pose.to_isometry();
    ceres::Problem problem(problem_options);
    problem.AddParameterBlock(pose.q, 4, &quaternion_manifold);
    problem.AddParameterBlock(pose.t, 3);
    int num_active = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!active[i]) continue;
      // Pass 1 skips only matches the residuals cannot evaluate (behind a camera); pass 2 also
      // drops those whose chi2 exceeds the threshold after pass 1.
      const bool keep = pass == 0 ? match_is_inlier(cam, matches[i], current, std::numeric_limits<double>::max())
                                  : match_is_inlier(cam, matches[i], current, options.chi2_threshold);
      if (!keep) {
        active[i] = false;
        continue;
      }
      problem.AddResidualBlock(costs[2 * i].get(), robust ? huber(measurement_in_1(matches[i])) : nullptr, pose.q, pose.t);
      problem.AddResidualBlock(costs[2 * i + 1].get(), robust ? huber(measurement_in_2(matches[i])) : nullptr, pose.q,
                               pose.t);
      ++num_active;
    }
    if (num_active < options.min_matches) {
      if (pass == 0) return failure(T_12_initial, n, "too few matches in front of both cameras");
      break;
    }
    solver_options.max_num_iterations = pass_iterations[pass];
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    if (!summary.IsSolutionUsable() || !pose.is_finite()) {
      return failure(T_12_initial, n, "ceres failed: " + summary.message);
    }
  }

  RelativePoseResult result;
  result.ok = true;
  result.T_12 = pose.to_isometry();
  result.inliers.assign(n, false);
  for (size_t i = 0; i < n; ++i) {
    result.inliers[i] = is_usable(matches[i]) && match_is_inlier(cam, matches[i], result.T_12, options.chi2_threshold);
    result.num_inliers += result.inliers[i] ? 1 : 0;
  }
  result.message = "inliers " + std::to_string(result.num_inliers) + "/" + std::to_string(n);
  return result;
}

}  // namespace edge_slam
