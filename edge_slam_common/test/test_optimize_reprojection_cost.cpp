// The bundle adjustment residual's hand-written Jacobians against automatic differentiation
// of the same residual (src/optimize is private: the test reaches its header directly).
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "../src/optimize/reprojection_cost.h"
#include "edge_slam/sim/synthetic_camera.h"

using namespace edge_slam;
using namespace edge_slam::optimize_detail;

namespace {

struct Evaluation {
  bool ok = false;
  double r[3] = {0, 0, 0};
  double jq[12] = {}, jt[9] = {}, jx[9] = {};
};

Evaluation evaluate(const ceres::CostFunction& f, const double* q, const double* t, const double* X) {
  Evaluation e;
  const double* params[3] = {q, t, X};
  double* jacobians[3] = {e.jq, e.jt, e.jx};
  e.ok = f.Evaluate(params, e.r, jacobians);
  return e;
}

void expect_same(const Evaluation& a, const Evaluation& b, const char* what) {
  ASSERT_EQ(a.ok, b.ok) << what;
  if (!a.ok) return;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a.r[i], b.r[i], 1e-9 * (1.0 + std::abs(b.r[i]))) << what << " r" << i;
  for (int i = 0; i < 12; ++i) EXPECT_NEAR(a.jq[i], b.jq[i], 1e-7 * (1.0 + std::abs(b.jq[i]))) << what << " dq" << i;
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(a.jt[i], b.jt[i], 1e-7 * (1.0 + std::abs(b.jt[i]))) << what << " dt" << i;
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(a.jx[i], b.jx[i], 1e-7 * (1.0 + std::abs(b.jx[i]))) << what << " dX" << i;
}

TEST(ReprojectionCost, AnalyticJacobiansMatchAutodiffForStereoAndMonocular) {
  const PinholeCamera cam = synthetic_room_camera(30.0);
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
    const Eigen::Vector3d t(0.3 * n(rng), 0.3 * n(rng), 0.3 * n(rng));
    // A world point placed 0.5-4 m in front of the camera.
    const Eigen::Vector3d Xc(0.5 * n(rng), 0.5 * n(rng), 0.5 + 3.5 * std::abs(n(rng)) / 3.0);
    const Eigen::Vector3d Xw = q.inverse() * (Xc - t);
    PixelMeasurement m;
    m.pixel = cam.project(Xc) + Eigen::Vector2d(n(rng), n(rng));
    m.inv_sigma2 = 1.0 / std::pow(1.2, 2 * (trial % 4));
    m.right_x = trial % 3 == 0 ? -1.0 : m.pixel.x() - cam.bf / Xc.z() + n(rng);
    const std::unique_ptr<ceres::CostFunction> analytic(make_reprojection_cost(cam, m));
    const std::unique_ptr<ceres::CostFunction> autodiff(make_reprojection_cost_autodiff(cam, m));
    ASSERT_EQ(analytic->num_residuals(), 3);
    expect_same(evaluate(*analytic, q.coeffs().data(), t.data(), Xw.data()),
                evaluate(*autodiff, q.coeffs().data(), t.data(), Xw.data()), m.is_stereo() ? "stereo" : "mono");
  }
}

TEST(ReprojectionCost, MonocularThirdResidualIsZeroAndChi2MatchesTheCheck) {
  const PinholeCamera cam = synthetic_room_camera(30.0);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d t(0.1, -0.05, 0.2), Xw(0.3, 0.2, 2.0);
  PixelMeasurement m;
  m.pixel = cam.project(q * Xw + t) + Eigen::Vector2d(1.5, -2.0);
  m.inv_sigma2 = 0.5;
  const std::unique_ptr<ceres::CostFunction> f(make_reprojection_cost(cam, m));
  const Evaluation e = evaluate(*f, q.coeffs().data(), t.data(), Xw.data());
  ASSERT_TRUE(e.ok);
  EXPECT_EQ(e.r[2], 0.0);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(e.jq[8 + c], 0.0);
  const double chi2 = e.r[0] * e.r[0] + e.r[1] * e.r[1];
  EXPECT_NEAR(chi2, evaluate_reprojection(cam, m, q, t, Xw).chi2, 1e-9);
}

TEST(ReprojectionCost, PointBehindTheCameraIsRefused) {
  const PinholeCamera cam = synthetic_room_camera(30.0);
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  const Eigen::Vector3d t = Eigen::Vector3d::Zero(), Xw(0.1, 0.1, -1.0);
  PixelMeasurement m;
  m.pixel = Eigen::Vector2d(320, 240);
  m.right_x = 300;
  const std::unique_ptr<ceres::CostFunction> analytic(make_reprojection_cost(cam, m));
  const std::unique_ptr<ceres::CostFunction> autodiff(make_reprojection_cost_autodiff(cam, m));
  EXPECT_FALSE(evaluate(*analytic, q.coeffs().data(), t.data(), Xw.data()).ok);
  EXPECT_FALSE(evaluate(*autodiff, q.coeffs().data(), t.data(), Xw.data()).ok);
}

}  // namespace
