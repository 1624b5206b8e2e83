// The pose-only optimiser's single hand-written residual block (src/optimize/pose_batch_cost.h)
// against the formulation it replaced: one autodiff residual block per observation with its
// own Huber loss, rebuilt each round. (1) Rows and Jacobians equal the autodiff ones (scaled by
// sqrt(rho') when robust) and the block cost is the per-observation robust sum; (2) the whole
// 4-round optimisation takes the same steps: with only 2 iterations per round the result
// depends on every step, and poses and inlier flags agree to rounding.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "../src/optimize/pose_batch_cost.h"
#include "../src/optimize/pose_parameters.h"
#include "../src/optimize/reprojection_cost.h"
#include "edge_slam/optimize/pose_optimizer.h"
#include "edge_slam/sim/synthetic_camera.h"

using namespace edge_slam;
using namespace edge_slam::optimize_detail;

namespace {

struct Scene {
  PinholeCamera cam = synthetic_room_camera(30.0);
  Eigen::Isometry3d T_cw_true = Eigen::Isometry3d::Identity(), T_cw_start = Eigen::Isometry3d::Identity();
  std::vector<PoseObservation> obs;
};

// Points 1-5 m away, half stereo, levels 0-3, some gross outliers; the start pose is off by
// a few degrees and centimetres so that LM needs several steps.
Scene make_scene(unsigned seed, int n = 200, double outliers = 0.15) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  s.T_cw_true.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  s.T_cw_true.translation() = Eigen::Vector3d(0.2, -0.1, 0.4);
  const Eigen::Isometry3d T_wc = s.T_cw_true.inverse();
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 + 4.0 * unit(rng);
    const double u = s.cam.width * unit(rng), v = s.cam.height * unit(rng);
    PoseObservation o;
    o.point_world = T_wc * s.cam.unproject(u, v, z);
    const double sigma = std::pow(1.2, i % 4);
    o.inv_sigma2 = 1.0 / (sigma * sigma);
    o.pixel = {u + sigma * noise(rng), v + sigma * noise(rng)};
    if (i % 2 == 0) o.right_x = o.pixel.x() - s.cam.bf / z + sigma * noise(rng);
    if (unit(rng) < outliers) o.pixel += Eigen::Vector2d(40 * (unit(rng) - 0.5), 40 * (unit(rng) - 0.5));
    s.obs.push_back(o);
  }
  s.T_cw_start = s.T_cw_true;
  s.T_cw_start.linear() = Eigen::AngleAxisd(0.04, Eigen::Vector3d::UnitX()).toRotationMatrix() * s.T_cw_true.rotation();
  s.T_cw_start.translation() += Eigen::Vector3d(0.03, -0.02, 0.05);
  return s;
}

PixelMeasurement measurement(const PoseObservation& o) { return PixelMeasurement{o.pixel, o.right_x, o.inv_sigma2}; }

// The formulation before pose_batch_cost.h, kept as the reference: per observation an autodiff
// block and its own Huber loss, a new problem per round.
PoseOptimizationResult reference_optimize(const PinholeCamera& cam, const std::vector<PoseObservation>& obs,
                                          Eigen::Isometry3d& T_cw, std::vector<bool>& is_outlier,
                                          const PoseOptimizationOptions& options) {
  std::vector<bool> outlier(obs.size(), false);
  PoseParameters pose = PoseParameters::from_isometry(T_cw);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs(obs.size());
  for (size_t i = 0; i < obs.size(); ++i)
    costs[i].reset(make_pose_only_reprojection_cost(cam, measurement(obs[i]), obs[i].point_world));
  ceres::HuberLoss huber_mono(std::sqrt(kChi2Mono)), huber_stereo(std::sqrt(kChi2Stereo));
  ceres::EigenQuaternionManifold manifold;
  ceres::Problem::Options po;
  po.cost_function_ownership = po.loss_function_ownership = po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  so.max_num_iterations = options.iterations_per_round;
  so.logging_type = ceres::SILENT;
  for (int round = 0; round < options.rounds; ++round) {
    const bool robust = round + 1 < options.rounds;
    ceres::Problem problem(po);
    problem.AddParameterBlock(pose.q, 4, &manifold);
    problem.AddParameterBlock(pose.t, 3);
    for (size_t i = 0; i < obs.size(); ++i) {
      if (outlier[i]) continue;
      const PixelMeasurement m = measurement(obs[i]);
      if (evaluate_reprojection(cam, m, pose.quaternion(), pose.translation(), obs[i].point_world).depth <= kMinDepth) {
        outlier[i] = true;
        continue;
      }
      problem.AddResidualBlock(costs[i].get(), robust ? (m.is_stereo() ? &huber_stereo : &huber_mono) : nullptr,
                               pose.q, pose.t);
    }
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    EXPECT_TRUE(summary.IsSolutionUsable());
    for (size_t i = 0; i < obs.size(); ++i) {
      const PixelMeasurement m = measurement(obs[i]);
      outlier[i] = is_reprojection_outlier(
          evaluate_reprojection(cam, m, pose.quaternion(), pose.translation(), obs[i].point_world), m);
    }
  }
  PoseOptimizationResult r;
  r.ok = true;
  for (bool o : outlier) r.inliers += o ? 0 : 1;
  T_cw = pose.to_isometry();
  is_outlier = outlier;
  return r;
}

}  // namespace

TEST(PoseBatchCost, RowsAndJacobiansAreTheRobustifiedPerObservationOnes) {
  const Scene s = make_scene(1, 40);
  std::vector<PixelMeasurement> ms;
  std::vector<Eigen::Vector3d> pts;
  for (const auto& o : s.obs) {
    ms.push_back(measurement(o));
    pts.push_back(o.point_world);
  }
  PoseBatchCost batch(s.cam, ms, pts, PoseBatchCost::Form::kRows);
  batch.set_active(3, false);
  const PoseParameters pose = PoseParameters::from_isometry(s.T_cw_start);
  const double* params[2] = {pose.q, pose.t};
  const int rows = batch.num_residuals();
  std::vector<double> r(rows), jq(rows * 4), jt(rows * 3);
  double* jac[2] = {jq.data(), jt.data()};
  for (const bool robust : {true, false}) {
    batch.set_robust(robust);
    ASSERT_TRUE(batch.Evaluate(params, r.data(), jac));
    double expected_sum = 0;
    int row = 0;
    for (size_t i = 0; i < s.obs.size(); ++i) {
      const int n = ms[i].is_stereo() ? 3 : 2;
      std::unique_ptr<ceres::CostFunction> ref(make_pose_only_reprojection_cost(s.cam, ms[i], pts[i]));
      double rr[3], rq[12], rt[9];
      double* rj[2] = {rq, rt};
      ASSERT_TRUE(ref->Evaluate(params, rr, rj));
      double sq = 0;
      for (int k = 0; k < n; ++k) sq += rr[k] * rr[k];
      double rho[3] = {sq, 1, 0};
      if (robust) ceres::HuberLoss(std::sqrt(ms[i].is_stereo() ? kChi2Stereo : kChi2Mono)).Evaluate(sq, rho);
      const double scale = i == 3 ? 0.0 : std::sqrt(rho[1]);
      if (i != 3) expected_sum += rho[0];
      for (int k = 0; k < n; ++k, ++row) {
        EXPECT_NEAR(r[row], scale * rr[k], 1e-9 * (1 + std::abs(rr[k]))) << "obs " << i << " row " << k;
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(jq[4 * row + c], scale * rq[4 * k + c], 1e-7 * (1 + std::abs(rq[4 * k + c])));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(jt[3 * row + c], scale * rt[3 * k + c], 1e-7 * (1 + std::abs(rt[3 * k + c])));
      }
    }
    EXPECT_EQ(row, rows);
    EXPECT_NEAR(batch.last_robust_sum(), expected_sum, 1e-9 * expected_sum);
    // Some observations must be in Huber's linear part, or the robust branch is untested.
    if (robust) {
      double plain = 0;
      for (int k = 0; k < rows; ++k) plain += r[k] * r[k];
      EXPECT_GT(std::abs(plain - expected_sum), 1.0);
    }
  }
  // A point behind the camera fails the evaluation, as the per-observation residual does.
  std::vector<Eigen::Vector3d> behind = pts;
  behind[0] = s.T_cw_start.inverse() * Eigen::Vector3d(0, 0, -1);
  PoseBatchCost bad(s.cam, ms, behind, PoseBatchCost::Form::kRows);
  EXPECT_FALSE(bad.Evaluate(params, r.data(), jac));
  bad.set_active(0, false);
  EXPECT_TRUE(bad.Evaluate(params, r.data(), jac));
}

TEST(PoseBatchCost, SquareRootFormHasTheRowsNormalEquationsAndCost) {
  const Scene s = make_scene(2, 60);
  std::vector<PixelMeasurement> ms;
  std::vector<Eigen::Vector3d> pts;
  for (const auto& o : s.obs) {
    ms.push_back(measurement(o));
    pts.push_back(o.point_world);
  }
  PoseBatchCost rows(s.cam, ms, pts, PoseBatchCost::Form::kRows), root(s.cam, ms, pts);
  rows.set_active(5, false);
  root.set_active(5, false);
  ASSERT_EQ(root.num_residuals(), PoseBatchCost::kSquareRootRows);
  const PoseParameters pose = PoseParameters::from_isometry(s.T_cw_start);
  const double* params[2] = {pose.q, pose.t};
  const int n = rows.num_residuals();
  // J as n x 7 (q then t) for both forms.
  auto evaluate = [&](const PoseBatchCost& f, int m, Eigen::MatrixXd& J, Eigen::VectorXd& r) {
    std::vector<double> res(m), jq(m * 4), jt(m * 3);
    double* jac[2] = {jq.data(), jt.data()};
    ASSERT_TRUE(f.Evaluate(params, res.data(), jac));
    J.resize(m, 7);
    r = Eigen::Map<Eigen::VectorXd>(res.data(), m);
    for (int i = 0; i < m; ++i) {
      for (int c = 0; c < 4; ++c) J(i, c) = jq[4 * i + c];
      for (int c = 0; c < 3; ++c) J(i, 4 + c) = jt[3 * i + c];
    }
  };
  // Ceres sees J times the manifold's plus-Jacobian (quaternion columns) in the tangent space:
  // that is what both forms must agree on (the square-root form computes nothing along q itself).
  Eigen::Matrix<double, 7, 6> plus = Eigen::Matrix<double, 7, 6>::Zero();
  {
    double M[12];
    ceres::EigenQuaternionManifold().PlusJacobian(pose.q, M);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 3; ++c) plus(r, c) = M[3 * r + c];
    plus.bottomRightCorner<3, 3>().setIdentity();
  }
  for (const bool robust : {true, false}) {
    rows.set_robust(robust);
    root.set_robust(robust);
    Eigen::MatrixXd J1, J2;
    Eigen::VectorXd r1, r2;
    evaluate(rows, n, J1, r1);
    evaluate(root, PoseBatchCost::kSquareRootRows, J2, r2);
    J1 = J1 * plus;
    J2 = J2 * plus;
    const Eigen::MatrixXd A1 = J1.transpose() * J1, A2 = J2.transpose() * J2;
    const Eigen::VectorXd g1 = J1.transpose() * r1, g2 = J2.transpose() * r2;
    EXPECT_LT((A1 - A2).cwiseAbs().maxCoeff(), 1e-9 * A1.cwiseAbs().maxCoeff());
    EXPECT_LT((g1 - g2).cwiseAbs().maxCoeff(), 1e-9 * g1.cwiseAbs().maxCoeff() + 1e-12);
    EXPECT_EQ(rows.last_robust_sum(), root.last_robust_sum());
    // The model of any step agrees: |J d|^2 and (J d).r.
    const Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Constant(1e-3);
    EXPECT_NEAR((J1 * d).squaredNorm(), (J2 * d).squaredNorm(), 1e-9 * (J1 * d).squaredNorm());
    EXPECT_NEAR((J1 * d).dot(r1), (J2 * d).dot(r2), 1e-9 * std::abs((J1 * d).dot(r1)) + 1e-12);
  }
}

TEST(PoseBatchCost, OptimisationTakesTheSameStepsAsPerObservationBlocks) {
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const Scene s = make_scene(seed);
    PoseOptimizationOptions options;
    options.iterations_per_round = seed % 3 == 0 ? 10 : 2;  // 2: the result depends on every step
    Eigen::Isometry3d T_new = s.T_cw_start, T_ref = s.T_cw_start;
    std::vector<bool> out_new, out_ref;
    const PoseOptimizationResult a = optimize_pose(s.cam, s.obs, T_new, out_new, options);
    const PoseOptimizationResult b = reference_optimize(s.cam, s.obs, T_ref, out_ref, options);
    ASSERT_TRUE(a.ok) << a.message;
    EXPECT_EQ(a.inliers, b.inliers) << "seed " << seed;
    EXPECT_EQ(out_new, out_ref) << "seed " << seed;
    EXPECT_LT((T_new.matrix() - T_ref.matrix()).cwiseAbs().maxCoeff(), 1e-9) << "seed " << seed;
    // And the comparison is not vacuous: the pose moved well beyond that tolerance.
    EXPECT_GT((T_new.matrix() - s.T_cw_start.matrix()).cwiseAbs().maxCoeff(), 1e-3) << "seed " << seed;
  }
}

