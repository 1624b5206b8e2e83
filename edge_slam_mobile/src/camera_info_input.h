// Intrinsics from a sensor_msgs/CameraInfo: the driver's calibration wins over the YAML one for
// what CameraInfo carries (size, K, plumb_bob / rational_polynomial distortion); the YAML still
// gives what it cannot (depth factor, virtual baseline, close/far threshold, name). The
// baseline is kept in metres, so bf follows the new fx.
#pragma once
#include <edge_slam/camera/pinhole_camera.h>
#include <sensor_msgs/CameraInfo.h>

#include <cmath>
#include <string>

namespace edge_slam_mobile {

// False (with `error` saying what was expected) when the message is unusable.
inline bool camera_from_info(const sensor_msgs::CameraInfo& info, const edge_slam::PinholeCamera& yaml,
                             edge_slam::PinholeCamera& out, std::string& error) {
  const double fx = info.K[0], fy = info.K[4], cx = info.K[2], cy = info.K[5];
  if (info.width == 0 || info.height == 0) {
    error = "camera_info has a zero image size";
    return false;
  }
  for (double v : {fx, fy, cx, cy})
    if (!std::isfinite(v)) {
      error = "camera_info K is not finite";
      return false;
    }
  if (fx <= 0 || fy <= 0) {
    error = "camera_info K has non-positive focal lengths (uncalibrated camera?)";
    return false;
  }
  const bool known_model = info.distortion_model.empty() || info.distortion_model == "plumb_bob" ||
                           info.distortion_model == "rational_polynomial";
  if (!known_model) {
    error = "camera_info distortion model '" + info.distortion_model + "', expected plumb_bob or rational_polynomial";
    return false;
  }
  if (info.distortion_model == "rational_polynomial") {
    for (size_t i = 5; i < info.D.size(); ++i)
      if (info.D[i] != 0) {
        error = "camera_info rational_polynomial with non-zero k4..k6 is not supported (plumb_bob terms only)";
        return false;
      }
  }
  edge_slam::PinholeCamera c = yaml;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = fx, c.fy = fy, c.cx = cx, c.cy = cy;
  double d[5] = {0, 0, 0, 0, 0};
  for (size_t i = 0; i < 5 && i < info.D.size(); ++i) {
    if (!std::isfinite(info.D[i])) {
      error = "camera_info D is not finite";
      return false;
    }
    d[i] = info.D[i];
  }
  c.k1 = d[0], c.k2 = d[1], c.p1 = d[2], c.p2 = d[3], c.k3 = d[4];
  if (yaml.fx > 0) c.bf = yaml.bf / yaml.fx * fx;
  out = c;
  return true;
}

inline bool same_intrinsics(const edge_slam::PinholeCamera& a, const edge_slam::PinholeCamera& b) {
  auto close = [](double x, double y) { return std::abs(x - y) <= 1e-6 * std::max(1.0, std::abs(x)); };
  return a.width == b.width && a.height == b.height && close(a.fx, b.fx) && close(a.fy, b.fy) &&
         close(a.cx, b.cx) && close(a.cy, b.cy) && close(a.k1, b.k1) && close(a.k2, b.k2) && close(a.p1, b.p1) &&
         close(a.p2, b.p2) && close(a.k3, b.k3);
}

}  // namespace edge_slam_mobile
