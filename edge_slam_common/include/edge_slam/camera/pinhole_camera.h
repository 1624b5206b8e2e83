// RGB-D pinhole camera shared by every module: intrinsics, distortion, the virtual stereo
// baseline used by ORB-SLAM2-style RGB-D tracking, and the depth conventions.
// Poses throughout the core are Eigen::Isometry3d; T_cw maps world points into the camera.
#pragma once
#include <Eigen/Core>
#include <string>

namespace edge_slam {

struct PinholeCamera {
  std::string name;
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;  // OpenCV radial-tangential model
  double bf = 0;             // baseline (m) * fx: right_x = u - bf / z
  double depth_factor = 1;   // raw 16UC1 depth value / depth_factor = metres
  double th_depth = 0;       // close/far threshold in metres (ORB-SLAM2: ThDepth * bf / fx)
  double fps = 30;
  // Rolling shutter: seconds from the first to the last row's exposure (top row first);
  // 0 = global shutter. Compensated with the tracker's velocity (data/rolling_shutter.h).
  double rolling_shutter_readout = 0;

  double baseline() const { return bf / fx; }
  bool has_distortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0; }

  Eigen::Vector2d project(const Eigen::Vector3d& p_cam) const {
    const double inv_z = 1.0 / p_cam.z();
    return {fx * p_cam.x() * inv_z + cx, fy * p_cam.y() * inv_z + cy};
  }
  // Undistorted pixel + depth (metres) -> point in the camera frame.
  Eigen::Vector3d unproject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
};

}  // namespace edge_slam
