#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "edge_slam/optimize/pose_optimizer.h"

using namespace edge_slam;

namespace {

PinholeCamera make_camera() { return synthetic_room_camera(30.0); }

Eigen::Isometry3d make_pose(const Eigen::Vector3d& axis_angle, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (axis_angle.norm() > 0) T.linear() = Eigen::AngleAxisd(axis_angle.norm(), axis_angle.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

double rotation_error_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

double translation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  // Camera centres, so the comparison does not depend on the rotation error.
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

struct Scene {
  PinholeCamera cam = make_camera();
  Eigen::Isometry3d T_cw_true;
  std::vector<PoseObservation> obs;
  std::vector<bool> planted_outlier;
};

Scene make_scene(int num_points, double outlier_ratio, unsigned seed) {
  Scene s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  s.T_cw_true = make_pose({0.1, -0.2, 0.05}, {0.3, -0.1, 0.5});
  const Eigen::Isometry3d T_wc = s.T_cw_true.inverse();
  for (int i = 0; i < num_points; ++i) {
    const double z = 1.0 + 4.0 * unit(rng);
    const double u = s.cam.width * unit(rng), v = s.cam.height * unit(rng);
    const Eigen::Vector3d Xc = s.cam.unproject(u, v, z);
    PoseObservation o;
    o.point_world = T_wc * Xc;
    o.pixel = {u, v};
    if (i % 2 == 0) o.right_x = u - s.cam.bf / z;
    o.inv_sigma2 = 1.0 / std::pow(1.2, 2 * (i % 4));  // pyramid levels 0..3
    const bool outlier = unit(rng) < outlier_ratio;
    if (outlier) {
      o.pixel = {s.cam.width * unit(rng), s.cam.height * unit(rng)};
      if (o.right_x >= 0) o.right_x = o.pixel.x() - s.cam.bf / (1.0 + 4.0 * unit(rng));
    }
    s.obs.push_back(o);
    s.planted_outlier.push_back(outlier);
  }
  return s;
}

}  // namespace

TEST(PoseOptimizer, RecoversPerturbedPoseAndFlagsOutliers) {
  Scene s = make_scene(200, 0.2, 7);
  Eigen::Isometry3d T_cw = make_pose(Eigen::Vector3d(1, 2, -1).normalized() * (3.0 * M_PI / 180.0),
                                     Eigen::Vector3d::Zero()) *
                           s.T_cw_true;
  T_cw.translation() += Eigen::Vector3d(0.03, -0.03, 0.028);  // ~5 cm
  std::vector<bool> is_outlier(s.obs.size(), false);

  const PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  ASSERT_TRUE(r.ok) << r.message;

  const double t_err = translation_error(T_cw, s.T_cw_true);
  const double r_err = rotation_error_deg(T_cw, s.T_cw_true);
  EXPECT_LT(t_err, 1e-3);
  EXPECT_LT(r_err, 0.05);

  int planted = 0, caught = 0, false_alarms = 0;
  for (size_t i = 0; i < s.obs.size(); ++i) {
    planted += s.planted_outlier[i];
    if (s.planted_outlier[i] && is_outlier[i]) ++caught;
    if (!s.planted_outlier[i] && is_outlier[i]) ++false_alarms;
  }
  EXPECT_GE(caught, 0.9 * planted);
  EXPECT_EQ(false_alarms, 0);
  EXPECT_EQ(r.inliers, static_cast<int>(s.obs.size()) - caught - false_alarms);
  std::printf("pose-only: t_err %.2e m, r_err %.2e deg, caught %d/%d outliers, %d false alarms\n",
              t_err, r_err, caught, planted, false_alarms);
}

TEST(PoseOptimizer, RetestsObservationsFlaggedOnInput) {
  Scene s = make_scene(100, 0.0, 3);
  Eigen::Isometry3d T_cw = s.T_cw_true;
  std::vector<bool> is_outlier(s.obs.size(), true);
  for (size_t i = 0; i < 10; ++i) is_outlier[i] = false;
  const PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.inliers, 100);
}

TEST(PoseOptimizer, TooFewObservationsLeavesPoseUnchanged) {
  Scene s = make_scene(2, 0.0, 1);
  Eigen::Isometry3d T_cw = make_pose({0.01, 0, 0}, {0.1, 0, 0});
  const Eigen::Isometry3d before = T_cw;
  std::vector<bool> is_outlier(2, false);
  const PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
  EXPECT_TRUE(T_cw.isApprox(before, 0.0));
}

TEST(PoseOptimizer, NonFiniteInputIsRejected) {
  Scene s = make_scene(3, 0.0, 2);
  s.obs[1].point_world.x() = std::nan("");
  Eigen::Isometry3d T_cw = s.T_cw_true;
  const Eigen::Isometry3d before = T_cw;
  std::vector<bool> is_outlier(3, false);
  PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(T_cw.isApprox(before, 0.0));

  Scene big = make_scene(50, 0.0, 2);
  Eigen::Isometry3d nan_pose = big.T_cw_true;
  nan_pose.translation().x() = std::nan("");
  std::vector<bool> flags;
  r = optimize_pose(big.cam, big.obs, nan_pose, flags);
  EXPECT_FALSE(r.ok);
}

TEST(PoseOptimizer, NanObservationAmongManyIsAnOutlier) {
  Scene s = make_scene(60, 0.0, 5);
  s.obs[4].pixel.y() = std::nan("");
  Eigen::Isometry3d T_cw = s.T_cw_true;
  std::vector<bool> is_outlier;  // resized by the optimiser
  const PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  ASSERT_TRUE(r.ok);
  ASSERT_EQ(is_outlier.size(), s.obs.size());
  EXPECT_TRUE(is_outlier[4]);
  EXPECT_EQ(r.inliers, 59);
  EXPECT_TRUE(T_cw.matrix().allFinite());
}

TEST(PoseOptimizer, PointsBehindCameraAreOutliers) {
  Scene s = make_scene(40, 0.0, 9);
  const Eigen::Isometry3d T_wc = s.T_cw_true.inverse();
  s.obs[0].point_world = T_wc * Eigen::Vector3d(0.1, 0.1, -2.0);
  Eigen::Isometry3d T_cw = s.T_cw_true;
  std::vector<bool> is_outlier(s.obs.size(), false);
  const PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(is_outlier[0]);
  EXPECT_EQ(r.inliers, 39);
}

TEST(PoseOptimizer, NoisyPixelsStayAccurate) {
  Scene s = make_scene(300, 0.2, 13);
  std::mt19937 rng(99);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (PoseObservation& o : s.obs) {
    o.pixel += Eigen::Vector2d(noise(rng), noise(rng));
    if (o.right_x >= 0) o.right_x += noise(rng);
  }
  Eigen::Isometry3d T_cw = s.T_cw_true;
  T_cw.translation() += Eigen::Vector3d(-0.04, 0.02, 0.02);
  std::vector<bool> is_outlier(s.obs.size(), false);
  const PoseOptimizationResult r = optimize_pose(s.cam, s.obs, T_cw, is_outlier);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_LT(translation_error(T_cw, s.T_cw_true), 0.005);
  EXPECT_LT(rotation_error_deg(T_cw, s.T_cw_true), 0.1);
  int caught = 0, planted = 0;
  for (size_t i = 0; i < s.obs.size(); ++i) {
    planted += s.planted_outlier[i];
    caught += s.planted_outlier[i] && is_outlier[i];
  }
  EXPECT_GE(caught, 0.9 * planted);
  std::printf("pose-only, 0.5 px noise: t_err %.2e m, r_err %.3f deg, %d inliers, caught %d/%d\n",
              translation_error(T_cw, s.T_cw_true), rotation_error_deg(T_cw, s.T_cw_true), r.inliers,
              caught, planted);
}
