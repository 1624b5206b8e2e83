#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "edge_slam/optimize/relative_pose_optimizer.h"

using namespace edge_slam;

namespace {

PinholeCamera make_camera() { return synthetic_room_camera(30.0); }

Eigen::Isometry3d true_T_12() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d(0.1, 1.0, 0.0).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.4, 0.05, 0.1);
  return T;
}

// Points seen by both keyframes; each keyframe's map point carries its own depth-like error,
// pixels carry noise_px, and outlier matches pair unrelated points and keypoints.
std::vector<RelativePoseMatch> make_matches(int n, double outlier_ratio, double noise_px, double point_noise,
                                            std::vector<bool>& planted_outlier) {
  const PinholeCamera cam = make_camera();
  const Eigen::Isometry3d T_12 = true_T_12(), T_21 = T_12.inverse();
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<RelativePoseMatch> matches;
  while (static_cast<int>(matches.size()) < n) {
    const Eigen::Vector3d X1 = cam.unproject(cam.width * unit(rng), cam.height * unit(rng), 1.5 + 3.0 * unit(rng));
    const Eigen::Vector3d X2 = T_21 * X1;
    const Eigen::Vector2d uv2 = cam.project(X2);
    if (X2.z() <= 0 || uv2.x() < 0 || uv2.y() < 0 || uv2.x() >= cam.width || uv2.y() >= cam.height) continue;
    RelativePoseMatch m;
    m.point_in_1 = X1 + point_noise * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    m.point_in_2 = X2 + point_noise * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    m.pixel_in_1 = cam.project(X1) + noise_px * Eigen::Vector2d(noise(rng), noise(rng));
    m.pixel_in_2 = uv2 + noise_px * Eigen::Vector2d(noise(rng), noise(rng));
    const bool outlier = unit(rng) < outlier_ratio;
    if (outlier) m.pixel_in_2 = {cam.width * unit(rng), cam.height * unit(rng)};
    matches.push_back(m);
    planted_outlier.push_back(outlier);
  }
  return matches;
}

Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
  d.linear() = Eigen::AngleAxisd(1.0 * M_PI / 180.0, Eigen::Vector3d(1, -1, 0.5).normalized()).toRotationMatrix();
  d.translation() = Eigen::Vector3d(0.02, -0.01, 0.015);
  return d * T;
}

}  // namespace

TEST(RelativePoseOptimizer, RefinesLoopTransformAndRejectsBadMatches) {
  std::vector<bool> planted;
  const auto matches = make_matches(120, 0.2, 0.0, 0.0, planted);
  const RelativePoseResult r = optimize_relative_pose(make_camera(), matches, perturbed(true_T_12()));
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Isometry3d T = true_T_12();
  EXPECT_LT((r.T_12.translation() - T.translation()).norm(), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(T.linear().transpose() * r.T_12.linear()).angle(), 1e-6);
  int wrong = 0;
  for (size_t i = 0; i < matches.size(); ++i) wrong += r.inliers[i] == planted[i];
  EXPECT_LE(wrong, 1);
}

TEST(RelativePoseOptimizer, NoisyMapPoints) {
  std::vector<bool> planted;
  const auto matches = make_matches(150, 0.2, 0.5, 0.003, planted);
  const RelativePoseResult r = optimize_relative_pose(make_camera(), matches, perturbed(true_T_12()));
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Isometry3d T = true_T_12();
  const double t_err = (r.T_12.translation() - T.translation()).norm();
  const double r_err = Eigen::AngleAxisd(T.linear().transpose() * r.T_12.linear()).angle() * 180.0 / M_PI;
  EXPECT_LT(t_err, 0.01);
  EXPECT_LT(r_err, 0.2);
  EXPECT_GE(r.num_inliers, 100);
  std::printf("relative pose (3 mm point noise, 0.5 px): t_err %.4f m, r_err %.3f deg, %d inliers\n", t_err, r_err,
              r.num_inliers);
}

TEST(RelativePoseOptimizer, DegenerateInput) {
  std::vector<bool> planted;
  auto matches = make_matches(2, 0.0, 0.0, 0.0, planted);
  RelativePoseResult r = optimize_relative_pose(make_camera(), matches, true_T_12());
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.T_12.isApprox(true_T_12(), 0.0));
  matches = make_matches(10, 0.0, 0.0, 0.0, planted);
  Eigen::Isometry3d bad = true_T_12();
  bad.translation().y() = std::nan("");
  EXPECT_FALSE(optimize_relative_pose(make_camera(), matches, bad).ok);
}
