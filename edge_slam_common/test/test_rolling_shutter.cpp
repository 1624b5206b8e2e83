// Rolling-shutter compensation: keypoints observed row by row by a moving camera are moved
// back to where a global-shutter camera at the frame's time stamp would have seen them.
#include "edge_slam/data/rolling_shutter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "edge_slam/sim/synthetic_camera.h"

using namespace edge_slam;

namespace {

constexpr double kReadout = 0.030;

PinholeCamera rolling_camera(double readout) {
  PinholeCamera c = synthetic_room_camera(30.0);
  c.rolling_shutter_readout = readout;
  return c;
}

struct Scene {
  std::vector<Eigen::Vector3d> at_stamp;  // points in the camera frame at the time stamp
  std::shared_ptr<const FrameFeatures> observed;  // what the rolling shutter recorded
};

// Each point is seen at the time its own row is read: solve tau = (y / h - 1/2) * readout for
// the row y it lands on (a fixed point; a few iterations converge for these speeds).
Scene observe(const PinholeCamera& cam, const CameraVelocity& v, size_t n, bool with_depth) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(40, cam.width - 40), uy(40, cam.height - 40), uz(0.8, 4.0);
  Scene s;
  auto f = std::make_shared<FrameFeatures>();
  f->camera = cam;
  f->pyramid = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d X = cam.unproject(ux(rng), uy(rng), uz(rng));
    Eigen::Vector3d X_row = X;
    for (int it = 0; it < 20; ++it) {
      const double tau = (cam.project(X_row).y() / cam.height - 0.5) * cam.rolling_shutter_readout;
      const double angle = v.angular.norm() * tau;
      const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, v.angular.normalized()).toRotationMatrix();
      X_row = R.transpose() * (X - v.linear * tau);
    }
    const Eigen::Vector2d uv = cam.project(X_row);
    cv::KeyPoint kp(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f, 0.f, 0.f, 0);
    f->keys.push_back(kp);
    f->depth.push_back(with_depth ? static_cast<float>(X_row.z()) : -1.f);
    f->right_x.push_back(with_depth ? static_cast<float>(uv.x() - cam.bf / X_row.z()) : -1.f);
    s.at_stamp.push_back(X);
  }
  f->keys_un = f->keys;
  f->descriptors = cv::Mat::zeros(static_cast<int>(n), 32, CV_8U);
  f->bounds = compute_image_bounds(cam);
  f->grid = FeatureGrid(f->keys_un, f->bounds);
  s.observed = f;
  return s;
}

double pixel_error(const PinholeCamera& cam, const FrameFeatures& f, size_t i, const Eigen::Vector3d& X) {
  return (cam.project(X) - Eigen::Vector2d(f.keys_un[i].pt.x, f.keys_un[i].pt.y)).norm();
}

}  // namespace

TEST(RollingShutter, MovesKeypointsAndDepthToTheTimeStamp) {
  const PinholeCamera cam = rolling_camera(kReadout);
  CameraVelocity v;
  v.angular = {0.6, 2.5, -0.4};  // ~150 deg/s, fr1_rpy's fastest turns
  v.linear = {0.3, -0.2, 0.4};
  const Scene s = observe(cam, v, 200, true);

  double worst_before = 0;
  for (size_t i = 0; i < s.at_stamp.size(); ++i)
    worst_before = std::max(worst_before, pixel_error(cam, *s.observed, i, s.at_stamp[i]));
  ASSERT_GT(worst_before, 10.0) << "the scene must be visibly sheared for the test to mean anything";

  const auto out = compensate_rolling_shutter(s.observed, v);
  ASSERT_NE(out, s.observed);
  for (size_t i = 0; i < s.at_stamp.size(); ++i) {
    EXPECT_LT(pixel_error(cam, *out, i, s.at_stamp[i]), 1e-3) << i;
    EXPECT_NEAR(out->depth[i], s.at_stamp[i].z(), 1e-5) << i;
    EXPECT_NEAR(out->right_x[i], out->keys_un[i].pt.x - cam.bf / out->depth[i], 1e-3) << i;
    // Raw keypoints (the measured pixels) and descriptors are left as they were.
    EXPECT_EQ(out->keys[i].pt, s.observed->keys[i].pt);
  }
  // The grid indexes the moved keypoints.
  const cv::Point2f p = out->keys_un[17].pt;
  const auto near = out->grid.in_area(out->keys_un, p.x, p.y, 1.f);
  EXPECT_NE(std::find(near.begin(), near.end(), size_t{17}), near.end());
}

TEST(RollingShutter, KeypointsWithoutDepthAreOnlyRotated) {
  const PinholeCamera cam = rolling_camera(kReadout);
  CameraVelocity v;
  v.angular = {-1.5, 0.8, 0.3};
  const Scene s = observe(cam, v, 50, false);
  v.linear = {5.0, 5.0, 5.0};  // unknown depth: a translation cannot be undone, and is ignored
  const auto out = compensate_rolling_shutter(s.observed, v);
  for (size_t i = 0; i < s.at_stamp.size(); ++i) {
    EXPECT_LT(pixel_error(cam, *out, i, s.at_stamp[i]), 1e-3) << i;
    EXPECT_FALSE(out->has_depth(i));
    EXPECT_LT(out->right_x[i], 0.f);
  }
}

TEST(RollingShutter, GlobalShutterStillCameraAndGlitchesChangeNothing) {
  CameraVelocity v;
  v.angular = {0.0, 3.0, 0.0};
  const Scene global = observe(rolling_camera(0.0), v, 20, true);
  EXPECT_EQ(compensate_rolling_shutter(global.observed, v), global.observed);  // same object

  CameraVelocity glitch;
  glitch.angular = {0.0, 40.0, 0.0};  // 2300 deg/s: a bad pose, not motion
  const Scene rolling = observe(rolling_camera(kReadout), v, 20, true);
  EXPECT_EQ(compensate_rolling_shutter(rolling.observed, glitch), rolling.observed);
  glitch.angular = {0.0, std::nan(""), 0.0};
  EXPECT_EQ(compensate_rolling_shutter(rolling.observed, glitch), rolling.observed);

  const Scene still = observe(rolling_camera(kReadout), CameraVelocity{}, 20, true);
  const auto out = compensate_rolling_shutter(still.observed, CameraVelocity{});
  for (size_t i = 0; i < out->size(); ++i) {
    EXPECT_EQ(out->keys_un[i].pt, still.observed->keys_un[i].pt);
    EXPECT_EQ(out->depth[i], still.observed->depth[i]);
  }
}

TEST(RollingShutter, VelocityFromTwoPoses) {
  const double dt = 1.0 / 30;
  const Eigen::Vector3d w(0.4, -1.2, 0.7), lin(0.5, 0.1, -0.3);
  Eigen::Isometry3d T_earlier_later = Eigen::Isometry3d::Identity();
  T_earlier_later.linear() = Eigen::AngleAxisd(w.norm() * dt, w.normalized()).toRotationMatrix();
  T_earlier_later.translation() = lin * dt;
  const CameraVelocity v = CameraVelocity::from_motion(T_earlier_later.inverse(), dt);
  EXPECT_LT((v.angular - w).norm(), 1e-9);
  EXPECT_LT((v.linear - lin).norm(), 1e-9);
  // No interval (repeated or reordered stamps): no velocity rather than a division by zero.
  const CameraVelocity none = CameraVelocity::from_motion(T_earlier_later.inverse(), 0.0);
  EXPECT_EQ(none.angular, Eigen::Vector3d::Zero());
  EXPECT_EQ(none.linear, Eigen::Vector3d::Zero());
}
