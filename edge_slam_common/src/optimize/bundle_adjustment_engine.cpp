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

// The problem resolved into parameter blocks and observation links, plus the Ceres objects the
// per-pass problems borrow: a pass rebuilds its ceres::Problem without re-creating 10^4
// autodiff cost functions.
class BundleAdjuster {
 public:
  BundleAdjuster(const BundleAdjustmentProblem& problem, const BaRunConfig& config)
      : problem_(problem), config_(config), abort_callback_(config.abort) {}

  BundleAdjustmentResult run() {
    std::string why;
    if (!index(&why)) return failure(problem_, why);
    prepare_solver();
    BundleAdjustmentResult result;
    for (size_t pass = 0; pass < config_.passes.size(); ++pass) {
      if (pass > 0 && config_.abort != nullptr && config_.abort->load()) {
        result.aborted = true;
        break;
      }
      if (pass > 0 && config_.drop_outliers_between_passes) drop_outliers();
      const PassOutcome outcome = run_pass(config_.passes[pass], &result.iterations, &why);
      if (outcome == PassOutcome::kFailed) return failure(problem_, why);
      if (outcome == PassOutcome::kNothingToDo) {
        if (pass == 0) return failure(problem_, why);
        break;
      }
      if (abort_callback_.raised()) {
        result.aborted = true;
        break;
      }
    }
    finish(&result);
    return result;
  }

 private:
  enum class PassOutcome { kSolved, kNothingToDo, kFailed };

  // One observation resolved to its keyframe and point slots.
  struct Link {
    size_t observation;
    size_t keyframe;
    size_t point;
    PixelMeasurement measurement;
  };

  ReprojectionCheck check(const Link& l) const {
    return evaluate_reprojection(problem_.camera, l.measurement, poses_[l.keyframe].quaternion(),
                                 poses_[l.keyframe].translation(), points_[l.point]);
  }

  bool index(std::string* why) {
    std::unordered_map<uint32_t, size_t> kf_slot, point_slot;
    for (size_t i = 0; i < problem_.keyframes.size(); ++i) {
      const BaKeyFrame& kf = problem_.keyframes[i];
      if (!kf_slot.emplace(kf.id, i).second) return (*why = "duplicate keyframe id " + std::to_string(kf.id), false);
      if (!is_finite_isometry(kf.T_cw)) return (*why = "keyframe " + std::to_string(kf.id) + " has a non-finite pose", false);
    }
    for (size_t i = 0; i < problem_.points.size(); ++i) {
      if (!point_slot.emplace(problem_.points[i].id, i).second) {
        return (*why = "duplicate point id " + std::to_string(problem_.points[i].id), false);
      }
    }
    if (!choose_fixed_keyframes()) return (*why = "no free keyframe", false);

    for (const BaKeyFrame& kf : problem_.keyframes) poses_.push_back(PoseParameters::from_isometry(kf.T_cw));
    for (const BaPoint& p : problem_.points) points_.push_back(p.position);
    initial_poses_ = poses_;
    initial_points_ = points_;

    for (size_t i = 0; i < problem_.observations.size(); ++i) {
      const BaObservation& o = problem_.observations[i];
      const auto kf = kf_slot.find(o.keyframe_id);
      const auto pt = point_slot.find(o.point_id);
      if (kf == kf_slot.end() || pt == point_slot.end()) {
        ++num_unknown_;
        continue;
      }
      if (!measurement_is_finite(o) || !points_[pt->second].allFinite()) {
        unusable_.push_back(i);
        continue;
      }
      links_.push_back(Link{i, kf->second, pt->second, PixelMeasurement{o.pixel, o.right_x, o.inv_sigma2}});
    }
    // Points behind a camera at the start cannot be evaluated by the residuals at all.
    active_.resize(links_.size());
    bool any_active = false;
    for (size_t k = 0; k < links_.size(); ++k) {
      active_[k] = check(links_[k]).depth > kMinDepth;
      any_active = any_active || active_[k];
    }
    if (!any_active) return (*why = "no usable observation", false);
    return true;
  }

  // Flags from the problem, plus the smallest id as gauge when asked; false if none is free.
  bool choose_fixed_keyframes() {
    const auto& kfs = problem_.keyframes;
    kf_fixed_.resize(kfs.size());
    for (size_t i = 0; i < kfs.size(); ++i) kf_fixed_[i] = kfs[i].fixed;
    const bool any_fixed = std::any_of(kf_fixed_.begin(), kf_fixed_.end(), [](bool f) { return f; });
    if (!any_fixed && config_.fix_smallest_id_if_none_fixed && !kfs.empty()) {
      const auto first = std::min_element(kfs.begin(), kfs.end(),
                                          [](const BaKeyFrame& a, const BaKeyFrame& b) { return a.id < b.id; });
      kf_fixed_[static_cast<size_t>(first - kfs.begin())] = true;
    }
    num_free_keyframes_ = static_cast<int>(std::count(kf_fixed_.begin(), kf_fixed_.end(), false));
    return num_free_keyframes_ > 0;
  }

  void prepare_solver() {
    costs_.resize(links_.size());
    for (size_t k = 0; k < links_.size(); ++k) costs_[k].reset(make_reprojection_cost(problem_.camera, links_[k].measurement));
    problem_options_.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options_.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options_.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    // The problem is built here from checked links (distinct blocks, fixed sizes): Ceres' own
    // per-residual checks (a parameter-block map lookup each) would only cost time.
    problem_options_.disable_all_safety_checks = true;
    // The reduced camera system is small for local windows: dense beats sparse factorisation there.
    solver_options_.linear_solver_type =
        num_free_keyframes_ <= kMaxKeyframesForDenseSchur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
    solver_options_.logging_type = ceres::SILENT;
    solver_options_.minimizer_progress_to_stdout = false;
    solver_options_.num_threads = std::max(1, config_.num_threads);
    solver_options_.callbacks.push_back(&abort_callback_);
  }

  void drop_outliers() {
    for (size_t k = 0; k < links_.size(); ++k) {
      active_[k] = active_[k] && !is_reprojection_outlier(check(links_[k]), links_[k].measurement);
    }
  }

  PassOutcome run_pass(const BaPass& pass, int* iterations, std::string* why) {
    ceres::Problem ceres_problem(problem_options_);
    int num_residuals = 0;
    for (size_t k = 0; k < links_.size(); ++k) {
      if (!active_[k]) continue;
      const Link& l = links_[k];
      ceres::LossFunction* loss = nullptr;
      if (pass.robust) loss = l.measurement.is_stereo() ? &huber_stereo_ : &huber_mono_;
      ceres_problem.AddResidualBlock(costs_[k].get(), loss, poses_[l.keyframe].q, poses_[l.keyframe].t,
                                     points_[l.point].data());
      ++num_residuals;
    }
    if (num_residuals == 0) return (*why = "no usable observation", PassOutcome::kNothingToDo);

    // Explicit Schur ordering (points eliminated first) spares Ceres its independent-set search.
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    int free_in_problem = 0;
    for (size_t i = 0; i < poses_.size(); ++i) {
      if (!ceres_problem.HasParameterBlock(poses_[i].q)) continue;
      ceres_problem.SetManifold(poses_[i].q, &quaternion_manifold_);
      if (kf_fixed_[i]) {
        ceres_problem.SetParameterBlockConstant(poses_[i].q);
        ceres_problem.SetParameterBlockConstant(poses_[i].t);
      } else {
        ++free_in_problem;
      }
      ordering->AddElementToGroup(poses_[i].q, 1);
      ordering->AddElementToGroup(poses_[i].t, 1);
    }
    if (free_in_problem == 0) return (*why = "no free keyframe has a usable observation", PassOutcome::kNothingToDo);
    for (size_t i = 0; i < points_.size(); ++i) {
      if (!ceres_problem.HasParameterBlock(points_[i].data())) continue;
      if (problem_.points[i].fixed) ceres_problem.SetParameterBlockConstant(points_[i].data());
      ordering->AddElementToGroup(points_[i].data(), 0);
    }
    solver_options_.linear_solver_ordering = ordering;
    solver_options_.max_num_iterations = pass.iterations;

    ceres::Solver::Summary summary;
    ceres::Solve(solver_options_, &ceres_problem, &summary);
    *iterations += summary.iterations.empty() ? 0 : static_cast<int>(summary.iterations.size()) - 1;
    bool finite = summary.IsSolutionUsable();
    for (const auto& p : poses_) finite = finite && p.is_finite();
    for (size_t i = 0; i < points_.size(); ++i) {
      finite = finite && (points_[i].allFinite() || !initial_points_[i].allFinite());
    }
    if (!finite) return (*why = "ceres failed: " + summary.message, PassOutcome::kFailed);
    return PassOutcome::kSolved;
  }

  // Final outlier classification, costs over the same (inlier) set, and the output copy.
  void finish(BundleAdjustmentResult* result) const {
    std::vector<bool> is_outlier(problem_.observations.size(), false);
    for (size_t i : unusable_) is_outlier[i] = true;
    for (const Link& l : links_) {
      if (is_reprojection_outlier(check(l), l.measurement)) is_outlier[l.observation] = true;
    }
    for (const Link& l : links_) {
      if (is_outlier[l.observation]) continue;
      result->final_cost += check(l).chi2;
      const ReprojectionCheck before =
          evaluate_reprojection(problem_.camera, l.measurement, initial_poses_[l.keyframe].quaternion(),
                                initial_poses_[l.keyframe].translation(), initial_points_[l.point]);
      result->initial_cost += std::isfinite(before.chi2) ? before.chi2 : 0.0;
    }
    for (size_t i = 0; i < is_outlier.size(); ++i) {
      if (is_outlier[i]) result->outlier_observations.push_back(i);
    }

    result->ok = true;
    result->keyframes = problem_.keyframes;
    for (size_t i = 0; i < poses_.size(); ++i) {
      if (!kf_fixed_[i]) result->keyframes[i].T_cw = poses_[i].to_isometry();  // fixed ones bit-exact
    }
    result->points = problem_.points;
    for (size_t i = 0; i < points_.size(); ++i) result->points[i].position = points_[i];
    result->message = std::to_string(result->iterations) + " iterations, " +
                      std::to_string(result->outlier_observations.size()) + " outlier observations" +
                      (num_unknown_ > 0 ? ", " + std::to_string(num_unknown_) + " observations with unknown ids ignored" : "") +
                      (result->aborted ? ", aborted" : "");
  }

  const BundleAdjustmentProblem& problem_;
  const BaRunConfig& config_;
  std::vector<bool> kf_fixed_;
  int num_free_keyframes_ = 0;
  std::vector<PoseParameters> poses_, initial_poses_;
  std::vector<Eigen::Vector3d> points_, initial_points_;
  std::vector<Link> links_;
  std::vector<bool> active_;      // per link: takes part in the next pass
  std::vector<size_t> unusable_;  // observations reported as outliers: data cannot be evaluated
  size_t num_unknown_ = 0;        // observations naming unknown ids: ignored

  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;  // per link
  ceres::HuberLoss huber_mono_{std::sqrt(kChi2Mono)};
  ceres::HuberLoss huber_stereo_{std::sqrt(kChi2Stereo)};
  ceres::EigenQuaternionManifold quaternion_manifold_;
  ceres::Problem::Options problem_options_;
  ceres::Solver::Options solver_options_;
  AbortCallback abort_callback_;
};

}  // namespace

BundleAdjustmentResult run_bundle_adjustment(const BundleAdjustmentProblem& problem,
                                             const BaRunConfig& config) {
  return BundleAdjuster(problem, config).run();
}

}  // namespace optimize_detail
}  // namespace edge_slam
