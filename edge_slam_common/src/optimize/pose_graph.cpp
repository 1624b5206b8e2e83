#include "edge_slam/optimize/pose_graph.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "pose_parameters.h"

namespace edge_slam {

using optimize_detail::PoseParameters;

namespace {

// Error transform E = measured^-1 * (T_jw * T_iw^-1); residual (2 * vec(q_E), t_E), which is
// ~ (rotation vector, translation) for small errors.
struct RelativePoseResidual {
  Eigen::Quaterniond q_measured;
  Eigen::Vector3d t_measured;
  double sqrt_weight;

  template <typename T>
  bool operator()(const T* q_i_ptr, const T* t_i_ptr, const T* q_j_ptr, const T* t_j_ptr, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_iw(q_i_ptr), q_jw(q_j_ptr);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_iw(t_i_ptr), t_jw(t_j_ptr);
    const Eigen::Quaternion<T> q_ji = q_jw * q_iw.conjugate();
    const Eigen::Matrix<T, 3, 1> t_ji = t_jw - q_ji * t_iw;

    const Eigen::Quaternion<T> q_m_inv = q_measured.conjugate().cast<T>();
    Eigen::Quaternion<T> q_err = q_m_inv * q_ji;
    const Eigen::Matrix<T, 3, 1> t_err = q_m_inv * (t_ji - t_measured.cast<T>());
    if (q_err.w() < T(0)) q_err.coeffs() = -q_err.coeffs();  // q and -q are the same rotation

    for (int k = 0; k < 3; ++k) {
      r[k] = T(2.0 * sqrt_weight) * q_err.vec()(k);
      r[3 + k] = T(sqrt_weight) * t_err(k);
    }
    return true;
  }
};

PoseGraphResult failure(const PoseGraphProblem& problem, const std::string& why) {
  PoseGraphResult r;
  r.message = why;
  r.vertices = problem.vertices;
  return r;
}

bool edge_is_usable(const PoseGraphEdge& e) {
  return e.from_id != e.to_id && e.T_to_from.matrix().allFinite() && std::isfinite(e.weight) &&
         e.weight > 0.0;
}

}  // namespace

PoseGraphResult optimize_pose_graph(const PoseGraphProblem& problem, const PoseGraphOptions& options) {
  std::unordered_map<uint32_t, size_t> slot;
  for (size_t i = 0; i < problem.vertices.size(); ++i) {
    if (!slot.emplace(problem.vertices[i].id, i).second) {
      return failure(problem, "duplicate vertex id " + std::to_string(problem.vertices[i].id));
    }
    if (!optimize_detail::is_finite_isometry(problem.vertices[i].T_cw)) {
      return failure(problem, "vertex " + std::to_string(problem.vertices[i].id) + " has a non-finite pose");
    }
  }
  std::vector<bool> fixed(problem.vertices.size());
  for (size_t i = 0; i < fixed.size(); ++i) fixed[i] = problem.vertices[i].fixed;
  if (!problem.vertices.empty() && std::none_of(fixed.begin(), fixed.end(), [](bool f) { return f; })) {
    const auto first = std::min_element(problem.vertices.begin(), problem.vertices.end(),
                                        [](const PoseGraphVertex& a, const PoseGraphVertex& b) { return a.id < b.id; });
    fixed[static_cast<size_t>(first - problem.vertices.begin())] = true;
  }

  std::vector<PoseParameters> poses(problem.vertices.size());
  for (size_t i = 0; i < poses.size(); ++i) poses[i] = PoseParameters::from_isometry(problem.vertices[i].T_cw);

  ceres::Problem ceres_problem;
  size_t skipped = 0, used = 0;
  bool touches_free_vertex = false;
  for (const PoseGraphEdge& e : problem.edges) {
    const auto from = slot.find(e.from_id), to = slot.find(e.to_id);
    if (from == slot.end() || to == slot.end() || !edge_is_usable(e)) {
      ++skipped;
      continue;
    }
    const size_t i = from->second, j = to->second;
    touches_free_vertex = touches_free_vertex || !fixed[i] || !fixed[j];
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseResidual, 6, 4, 3, 4, 3>(
        new RelativePoseResidual{Eigen::Quaterniond(e.T_to_from.linear()).normalized(),
                                 e.T_to_from.translation(), std::sqrt(e.weight)});
    ceres_problem.AddResidualBlock(cost, nullptr, poses[i].q, poses[i].t, poses[j].q, poses[j].t);
    ++used;
  }
  if (!touches_free_vertex) return failure(problem, "no usable edge touches a free vertex");

  for (size_t i = 0; i < poses.size(); ++i) {
    if (!ceres_problem.HasParameterBlock(poses[i].q)) continue;
    ceres_problem.SetManifold(poses[i].q, new ceres::EigenQuaternionManifold);
    if (fixed[i]) {
      ceres_problem.SetParameterBlockConstant(poses[i].q);
      ceres_problem.SetParameterBlockConstant(poses[i].t);
    }
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.iterations;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  solver_options.num_threads = std::max(1, options.num_threads);
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &ceres_problem, &summary);

  bool finite = summary.IsSolutionUsable();
  for (const auto& p : poses) finite = finite && p.is_finite();
  if (!finite) return failure(problem, "ceres failed: " + summary.message);

  PoseGraphResult result;
  result.ok = true;
  result.initial_cost = 2.0 * summary.initial_cost;  // Ceres reports half the squared norm
  result.final_cost = 2.0 * summary.final_cost;
  result.iterations = static_cast<int>(summary.iterations.empty() ? 0 : summary.iterations.size() - 1);
  result.vertices = problem.vertices;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (!fixed[i]) result.vertices[i].T_cw = poses[i].to_isometry();
  }
  result.message = std::to_string(used) + " edges, " + std::to_string(result.iterations) + " iterations" +
                   (skipped > 0 ? ", " + std::to_string(skipped) + " edges skipped" : "");
  return result;
}

}  // namespace edge_slam
