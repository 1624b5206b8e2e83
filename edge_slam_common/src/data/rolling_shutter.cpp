#include "edge_slam/data/rolling_shutter.h"

#include <cmath>

namespace edge_slam {
namespace {
// Beyond these the velocity is a tracking glitch rather than motion (a hand-held turn peaks
// near 200 deg/s, fr1_rpy included): compensating with it would shear the keypoints.
constexpr double kMaxAngularRate = 4 * M_PI;  // rad/s
constexpr double kMaxLinearSpeed = 10.0;      // m/s
}  // namespace

CameraVelocity CameraVelocity::from_motion(const Eigen::Isometry3d& T_later_earlier, double dt) {
  CameraVelocity v;
  if (!(dt > 0)) return v;
  // The earlier camera sees the later one at T_earlier_later = exp(dt * twist).
  const Eigen::Isometry3d T_earlier_later = T_later_earlier.inverse();
  const Eigen::AngleAxisd aa(T_earlier_later.rotation());
  v.angular = aa.axis() * (aa.angle() / dt);
  v.linear = T_earlier_later.translation() / dt;
  if (!v.angular.allFinite() || !v.linear.allFinite()) return CameraVelocity{};
  return v;
}

std::shared_ptr<const FrameFeatures> compensate_rolling_shutter(
    const std::shared_ptr<const FrameFeatures>& in, const CameraVelocity& velocity) {
  const PinholeCamera& cam = in->camera;
  if (cam.rolling_shutter_readout == 0 || cam.height <= 0) return in;
  if (!velocity.angular.allFinite() || !velocity.linear.allFinite() ||
      velocity.angular.norm() > kMaxAngularRate || velocity.linear.norm() > kMaxLinearSpeed)
    return in;
  auto out = std::make_shared<FrameFeatures>(*in);
  const double rate = velocity.angular.norm();
  const Eigen::Vector3d axis = rate > 0 ? Eigen::Vector3d(velocity.angular / rate) : Eigen::Vector3d::UnitZ();
  for (size_t i = 0; i < out->size(); ++i) {
    // Sensor rows are rows of the raw (distorted) image; the time stamp is the middle row's.
    const double tau = (in->keys[i].pt.y / cam.height - 0.5) * cam.rolling_shutter_readout;
    const bool with_depth = in->has_depth(i);
    const cv::Point2f& p = in->keys_un[i].pt;
    const Eigen::Vector3d X_row = cam.unproject(p.x, p.y, with_depth ? in->depth[i] : 1.0);
    Eigen::Vector3d X = Eigen::AngleAxisd(rate * tau, axis) * X_row;
    if (with_depth) X += velocity.linear * tau;  // without depth a translation cannot be undone
    if (!(X.z() > 0) || !X.allFinite()) continue;  // keep the measured keypoint
    const Eigen::Vector2d uv = cam.project(X);
    out->keys_un[i].pt = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    if (with_depth) {
      out->depth[i] = static_cast<float>(X.z());
      out->right_x[i] = static_cast<float>(uv.x() - cam.bf / X.z());
    }
  }
  out->grid = FeatureGrid(out->keys_un, out->bounds);
  return out;
}

}  // namespace edge_slam
