// Test helper: a camera pose turned by `yaw` radians about the y axis (the camera's vertical)
// and moved to (x, y, z): enough to tell poses apart in the pose-algebra tests.
#pragma once
#include <Eigen/Geometry>

namespace edge_slam {
namespace test_support {

inline Eigen::Isometry3d yaw_pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

}  // namespace test_support
}  // namespace edge_slam
