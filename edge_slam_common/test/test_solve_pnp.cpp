#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "edge_slam/solve/pnp_solver.h"

using namespace edge_slam;

namespace {

PinholeCamera make_camera() { return synthetic_room_camera(30.0); }

Eigen::Isometry3d true_pose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(-0.4, 0.2, 1.1);
  return T;
}

std::vector<PoseObservation> make_correspondences(int n, double outlier_ratio, double noise_px,
                                                  std::vector<bool>& planted_outlier) {
  const PinholeCamera cam = make_camera();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const Eigen::Isometry3d T_wc = true_pose().inverse();
  std::vector<PoseObservation> obs;
  for (int i = 0; i < n; ++i) {
    const double u = cam.width * unit(rng), v = cam.height * unit(rng), z = 1.0 + 4.0 * unit(rng);
    PoseObservation o;
    o.point_world = T_wc * cam.unproject(u, v, z);
    o.pixel = {u + noise(rng), v + noise(rng)};
    const bool outlier = unit(rng) < outlier_ratio;
    if (outlier) o.pixel = {cam.width * unit(rng), cam.height * unit(rng)};
    obs.push_back(o);
    planted_outlier.push_back(outlier);
  }
  return obs;
}

}  // namespace

TEST(PnpSolver, RecoversPoseWithOutliers) {
  std::vector<bool> planted;
  const auto obs = make_correspondences(150, 0.3, 0.0, planted);
  const PnpResult r = solve_pnp_ransac(make_camera(), obs);
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Isometry3d T = true_pose();
  const double rot_err = Eigen::AngleAxisd(T.linear().transpose() * r.T_cw.linear()).angle();
  const double c_err = (T.inverse().translation() - r.T_cw.inverse().translation()).norm();
  EXPECT_LT(rot_err, 1e-6);
  EXPECT_LT(c_err, 1e-6);
  int wrong = 0;
  for (size_t i = 0; i < obs.size(); ++i) wrong += r.inliers[i] == planted[i];
  EXPECT_LE(wrong, 2);
  std::printf("pnp: rot_err %.2e rad, centre err %.2e m, %d inliers, %d misclassified\n", rot_err,
              c_err, r.num_inliers, wrong);
}

TEST(PnpSolver, NoisyCorrespondences) {
  std::vector<bool> planted;
  const auto obs = make_correspondences(200, 0.3, 0.5, planted);
  const PnpResult r = solve_pnp_ransac(make_camera(), obs);
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Isometry3d T = true_pose();
  EXPECT_LT(Eigen::AngleAxisd(T.linear().transpose() * r.T_cw.linear()).angle(), 0.2 * M_PI / 180);
  EXPECT_LT((T.inverse().translation() - r.T_cw.inverse().translation()).norm(), 0.01);
}

TEST(PnpSolver, RejectsTooFewOrGarbage) {
  std::vector<bool> planted;
  auto obs = make_correspondences(5, 0.0, 0.0, planted);
  EXPECT_FALSE(solve_pnp_ransac(make_camera(), obs).ok);

  obs = make_correspondences(60, 1.0, 0.0, planted);  // all outliers
  PnpParams p;
  p.min_inliers = 20;
  const PnpResult r = solve_pnp_ransac(make_camera(), obs, p);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
  EXPECT_TRUE(r.T_cw.matrix().allFinite());
}
