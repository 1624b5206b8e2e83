#include "bundle_adjustment_engine.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_map>

#include "pose_parameters.h"
#include "reprojection_cost.h"

namespace edge_slam {
namespace optimize_detail {
namespace {

// Above this many free keyframes the reduced camera matrix is factorised sparsely.
constexpr int kMaxKeyframesForDenseSchur = 150;

// Stops the solver (keeping the current iterate) once the shared flag is raised.
class AbortCallback : public ceres::IterationCallback {
 public:
  explicit AbortCallback(std::atomic<bool>* flag) : flag_(flag) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    if (flag_ != nullptr && flag_->load()) {
      raised_ = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }
  bool raised() const { return raised_; }

 private:
  std::atomic<bool>* flag_;
  bool raised_ = false;
};

// One observation resolved to its keyframe and point slots.
struct Link {
  size_t observation;
  size_t keyframe;
  size_t point;
  PixelMeasurement measurement;
};

BundleAdjustmentResult failure(const BundleAdjustmentProblem& problem, const std::string& why) {
  BundleAdjustmentResult r;
  r.ok = false;
  r.message = why;
  r.keyframes = problem.keyframes;
  r.points = problem.points;
  return r;
}

bool measurement_is_finite(const BaObservation& o) {
  return o.pixel.allFinite() && std::isfinite(o.right_x) && std::isfinite(o.inv_sigma2) &&
         o.inv_sigma2 > 0.0;
}

}  // namespace

BundleAdjustmentResult run_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                             const BaRunConfig& config) {
  const PinholeCamera& cam = problem.camera;

  // ---- index keyframes and points, validate ----
  std::unordered_map<uint32_t, size_t> kf_slot, point_slot;
  for (size_t i = 0; i < problem.keyframes.size(); ++i) {
    if (!kf_slot.emplace(problem.keyframes[i].id, i).second) {
      return failure(problem, "duplicate keyframe id " + std::to_string(problem.keyframes[i].id));
    }
    if (!is_finite_isometry(problem.keyframes[i].T_cw)) {
      return failure(problem, "keyframe " + std::to_string(problem.keyframes[i].id) + " has a non-finite pose");
    }
  }
  for (size_t i = 0; i < problem.points.size(); ++i) {
    if (!point_slot.emplace(problem.points[i].id, i).second) {
      return failure(problem, "duplicate point id " + std::to_string(problem.points[i].id));
    }
  }

  std::vector<bool> kf_fixed(problem.keyframes.size());
  bool any_fixed = false;
  for (size_t i = 0; i < problem.keyframes.size(); ++i) {
    kf_fixed[i] = problem.keyframes[i].fixed;
    any_fixed = any_fixed || kf_fixed[i];
  }
  if (!any_fixed && config.fix_smallest_id_if_none_fixed && !problem.keyframes.empty()) {
    const auto first = std::min_element(problem.keyframes.begin(), problem.keyframes.end(),
                                        [](const BaKeyFrame& a, const BaKeyFrame& b) { return a.id < b.id; });
    kf_fixed[static_cast<size_t>(first - problem.keyframes.begin())] = true;
  }
  if (std::all_of(kf_fixed.begin(), kf_fixed.end(), [](bool f) { return f; })) {
    return failure(problem, "no free keyframe");
  }

  std::vector<PoseParameters> poses(problem.keyframes.size());
  for (size_t i = 0; i < poses.size(); ++i) poses[i] = PoseParameters::from_isometry(problem.keyframes[i].T_cw);
  std::vector<Eigen::Vector3d> points(problem.points.size());
  for (size_t i = 0; i < points.size(); ++i) points[i] = problem.points[i].position;

  std::vector<Link> links;
  std::vector<size_t> unusable;  // reported as outliers: their data cannot be evaluated
  size_t unknown = 0;
  for (size_t i = 0; i < problem.observations.size(); ++i) {
    const BaObservation& o = problem.observations[i];
    const auto kf = kf_slot.find(o.keyframe_id);
    const auto pt = point_slot.find(o.point_id);
    if (kf == kf_slot.end() || pt == point_slot.end()) {
      ++unknown;
      continue;
    }
    if (!measurement_is_finite(o) || !points[pt->second].allFinite()) {
      unusable.push_back(i);
      continue;
    }
    links.push_back(Link{i, kf->second, pt->second, PixelMeasurement{o.pixel, o.right_x, o.inv_sigma2}});
  }

  auto check = [&](const Link& l) {
    return evaluate_reprojection(cam, l.measurement, poses[l.keyframe].quaternion(),
                                 poses[l.keyframe].translation(), points[l.point]);
  };
  // Points behind a camera at the start cannot be evaluated by the residuals at all.
  std::vector<bool> active(links.size());
  size_t num_active = 0;
  for (size_t k = 0; k < links.size(); ++k) {
    active[k] = check(links[k]).depth > kMinDepth;
    num_active += active[k] ? 1 : 0;
  }
  if (num_active == 0) return failure(problem, "no usable observation");

  const std::vector<PoseParameters> initial_poses = poses;
  const std::vector<Eigen::Vector3d> initial_points = points;

  // Cost functions, losses and the manifold outlive the per-pass ceres::Problem, which only
  // borrows them: a pass rebuilds the problem without re-creating 10^4 autodiff objects.
  std::vector<std::unique_ptr<ceres::CostFunction>> costs(links.size());
  for (size_t k = 0; k < links.size(); ++k) costs[k].reset(make_reprojection_cost(cam, links[k].measurement));
  ceres::HuberLoss huber_mono(std::sqrt(kChi2Mono)), huber_stereo(std::sqrt(kChi2Stereo));
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;

  int num_free_keyframes = 0;
  for (bool f : kf_fixed) num_free_keyframes += f ? 0 : 1;
  ceres::Solver::Options solver_options;
  // The reduced camera system is small for local windows: dense beats sparse factorisation there.
  solver_options.linear_solver_type =
      num_free_keyframes <= kMaxKeyframesForDenseSchur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.num_threads = std::max(1, config.num_threads);
  AbortCallback abort_callback(config.abort);
  solver_options.callbacks.push_back(&abort_callback);

  BundleAdjustmentResult result;
  for (size_t pass = 0; pass < config.passes.size(); ++pass) {
    if (pass > 0 && config.abort != nullptr && config.abort->load()) {
      result.aborted = true;
      break;
    }
    if (pass > 0 && config.drop_outliers_between_passes) {
      for (size_t k = 0; k < links.size(); ++k) {
        active[k] = active[k] && !is_reprojection_outlier(check(links[k]), links[k].measurement);
      }
    }
    ceres::Problem ceres_problem(problem_options);
    int num_residuals = 0;
    for (size_t k = 0; k < links.size(); ++k) {
      if (!active[k]) continue;
      const Link& l = links[k];
      ceres::LossFunction* loss = nullptr;
      if (config.passes[pass].robust) loss = l.measurement.is_stereo() ? &huber_stereo : &huber_mono;
      ceres_problem.AddResidualBlock(costs[k].get(), loss, poses[l.keyframe].q, poses[l.keyframe].t,
                                     points[l.point].data());
      ++num_residuals;
    }
    if (num_residuals == 0) break;

    // Explicit Schur ordering (points eliminated first) spares Ceres its independent-set search.
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    int free_in_problem = 0;
    for (size_t i = 0; i < poses.size(); ++i) {
      if (!ceres_problem.HasParameterBlock(poses[i].q)) continue;
      ceres_problem.SetManifold(poses[i].q, &quaternion_manifold);
      if (kf_fixed[i]) {
        ceres_problem.SetParameterBlockConstant(poses[i].q);
        ceres_problem.SetParameterBlockConstant(poses[i].t);
      } else {
        ++free_in_problem;
      }
      ordering->AddElementToGroup(poses[i].q, 1);
      ordering->AddElementToGroup(poses[i].t, 1);
    }
    if (free_in_problem == 0) {
      if (pass == 0) return failure(problem, "no free keyframe has a usable observation");
      break;
    }
    for (size_t i = 0; i < points.size(); ++i) {
      if (!ceres_problem.HasParameterBlock(points[i].data())) continue;
      if (problem.points[i].fixed) ceres_problem.SetParameterBlockConstant(points[i].data());
      ordering->AddElementToGroup(points[i].data(), 0);
    }
    solver_options.linear_solver_ordering = ordering;
    solver_options.max_num_iterations = config.passes[pass].iterations;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &ceres_problem, &summary);
    result.iterations += static_cast<int>(summary.iterations.size() > 0 ? summary.iterations.size() - 1 : 0);
    bool finite = summary.IsSolutionUsable();
    for (const auto& p : poses) finite = finite && p.is_finite();
    for (size_t i = 0; i < points.size(); ++i) {
      finite = finite && (points[i].allFinite() || !initial_points[i].allFinite());
    }
    if (!finite) return failure(problem, "ceres failed: " + summary.message);
    if (abort_callback.raised()) {
      result.aborted = true;
      break;
    }
  }

  // ---- final classification and costs over the same (inlier) set ----
  std::vector<bool> is_outlier(problem.observations.size(), false);
  for (size_t i : unusable) is_outlier[i] = true;
  for (const Link& l : links) {
    if (is_reprojection_outlier(check(l), l.measurement)) is_outlier[l.observation] = true;
  }
  for (const Link& l : links) {
    if (is_outlier[l.observation]) continue;
    result.final_cost += check(l).chi2;
    const ReprojectionCheck before = evaluate_reprojection(
        cam, l.measurement, initial_poses[l.keyframe].quaternion(),
        initial_poses[l.keyframe].translation(), initial_points[l.point]);
    result.initial_cost += std::isfinite(before.chi2) ? before.chi2 : 0.0;
  }
  for (size_t i = 0; i < is_outlier.size(); ++i) {
    if (is_outlier[i]) result.outlier_observations.push_back(i);
  }

  result.ok = true;
  result.keyframes = problem.keyframes;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (!kf_fixed[i]) result.keyframes[i].T_cw = poses[i].to_isometry();  // fixed ones bit-exact
  }
  result.points = problem.points;
  for (size_t i = 0; i < points.size(); ++i) result.points[i].position = points[i];
  result.message = std::to_string(result.iterations) + " iterations, " +
                   std::to_string(result.outlier_observations.size()) + " outlier observations" +
                   (unknown > 0 ? ", " + std::to_string(unknown) + " observations with unknown ids ignored" : "") +
                   (result.aborted ? ", aborted" : "");
  return result;
}

}  // namespace optimize_detail
}  // namespace edge_slam
