// geometry_msgs/Pose <-> Eigen::Isometry3d, with the finiteness / unit-quaternion checks a
// receiver needs before trusting a pose; and the TF form for publishing poses.
#pragma once
#include <Eigen/Geometry>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/TransformStamped.h>

#include <string>

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

inline geometry_msgs::TransformStamped transform_to_message(const Eigen::Isometry3d& T_parent_child,
                                                            const ros::Time& stamp, const std::string& parent,
                                                            const std::string& child) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  const geometry_msgs::Pose p = pose_to_message(T_parent_child);
  t.transform.translation.x = p.position.x;
  t.transform.translation.y = p.position.y;
  t.transform.translation.z = p.position.z;
  t.transform.rotation = p.orientation;
  return t;
}

}  // namespace edge_slam
