// Private to src/optimize: a pose T_cw stored as the two Ceres parameter blocks every optimiser
// here uses, a unit quaternion (x, y, z, w; EigenQuaternionManifold order) and a translation.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace edge_slam {
namespace optimize_detail {

struct PoseParameters {
  double q[4] = {0, 0, 0, 1};
  double t[3] = {0, 0, 0};

  static PoseParameters from_isometry(const Eigen::Isometry3d& T) {
    PoseParameters p;
    const Eigen::Quaterniond q(T.linear());
    Eigen::Map<Eigen::Quaterniond>(p.q) = q.normalized();
    Eigen::Map<Eigen::Vector3d>(p.t) = T.translation();
    return p;
  }

  Eigen::Quaterniond quaternion() const { return Eigen::Map<const Eigen::Quaterniond>(q).normalized(); }
  Eigen::Vector3d translation() const { return Eigen::Map<const Eigen::Vector3d>(t); }

  Eigen::Isometry3d to_isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = quaternion().toRotationMatrix();
    T.translation() = translation();
    return T;
  }

  bool is_finite() const {
    for (double v : q) if (!std::isfinite(v)) return false;
    for (double v : t) if (!std::isfinite(v)) return false;
    return Eigen::Map<const Eigen::Vector4d>(q).norm() > 0.5;
  }
};

inline bool is_finite_isometry(const Eigen::Isometry3d& T) { return T.matrix().allFinite(); }

}  // namespace optimize_detail
}  // namespace edge_slam
