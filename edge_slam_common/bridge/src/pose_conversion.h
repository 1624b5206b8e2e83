// geometry_msgs/Pose <-> Eigen::Isometry3d, with the finiteness / unit-quaternion checks a
// receiver needs before trusting a pose.
#pragma once
#include <Eigen/Geometry>
#include <geometry_msgs/Pose.h>

#include <cmath>

namespace edge_slam {

inline geometry_msgs::Pose pose_to_message(const Eigen::Isometry3d& T) {
  geometry_msgs::Pose p;
  const Eigen::Quaterniond q(T.linear());
  p.position.x = T.translation().x();
  p.position.y = T.translation().y();
  p.position.z = T.translation().z();
  p.orientation.w = q.w();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  return p;
}

// False when any component is not finite or the quaternion is far from unit length.
inline bool pose_from_message(const geometry_msgs::Pose& p, Eigen::Isometry3d& T) {
  const double v[7] = {p.position.x, p.position.y, p.position.z, p.orientation.w,
                       p.orientation.x, p.orientation.y, p.orientation.z};
  for (double x : v)
    if (!std::isfinite(x)) return false;
  Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  if (std::abs(q.norm() - 1.0) > 1e-3) return false;
  q.normalize();
  T.setIdentity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return true;
}

}  // namespace edge_slam
