#include "reprojection_cost.h"

#include <ceres/autodiff_cost_function.h>

#include <cmath>
#include <limits>

namespace edge_slam {
namespace optimize_detail {
namespace {

// Transforms the world point into the camera and projects it; false when it is not in front.
template <typename T>
bool project_point(const PinholeCamera& cam, const T* q_xyzw, const T* t, const T* X,
                   T* u, T* v, T* z) {
  const Eigen::Map<const Eigen::Quaternion<T>> q(q_xyzw);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tc(t);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> Xw(X);
  const Eigen::Matrix<T, 3, 1> Xc = q * Xw + tc;
  if (!(Xc.z() > T(kMinDepth))) return false;
  const T inv_z = T(1.0) / Xc.z();
  *u = T(cam.fx) * Xc.x() * inv_z + T(cam.cx);
  *v = T(cam.fy) * Xc.y() * inv_z + T(cam.cy);
  *z = Xc.z();
  return true;
}

struct MonoResidual {
  PinholeCamera cam;
  Eigen::Vector2d pixel;
  double sqrt_info;

  template <typename T>
  bool operator()(const T* q, const T* t, const T* X, T* r) const {
    T u, v, z;
    if (!project_point(cam, q, t, X, &u, &v, &z)) return false;
    r[0] = T(sqrt_info) * (T(pixel.x()) - u);
    r[1] = T(sqrt_info) * (T(pixel.y()) - v);
    return true;
  }
};

struct StereoResidual {
  PinholeCamera cam;
  Eigen::Vector3d measured;  // u, v, u_right
  double sqrt_info;

  template <typename T>
  bool operator()(const T* q, const T* t, const T* X, T* r) const {
    T u, v, z;
    if (!project_point(cam, q, t, X, &u, &v, &z)) return false;
    const T u_right = u - T(cam.bf) / z;
    r[0] = T(sqrt_info) * (T(measured.x()) - u);
    r[1] = T(sqrt_info) * (T(measured.y()) - v);
    r[2] = T(sqrt_info) * (T(measured.z()) - u_right);
    return true;
  }
};

// The same residual with the world point held as a constant (pose-only optimisation).
template <typename Residual>
struct FixedPointResidual {
  Residual residual;
  Eigen::Vector3d point;

  template <typename T>
  bool operator()(const T* q, const T* t, T* r) const {
    const T X[3] = {T(point.x()), T(point.y()), T(point.z())};
    return residual(q, t, X, r);
  }
};

// Monocular residual of a point known in frame 1 observed in frame 2, for the pose T_12:
// the point is mapped by T_21 = T_12^-1 (quaternion conjugate, t_21 = -(q_21 * t_12)).
struct InversePoseResidual {
  MonoResidual residual;
  Eigen::Vector3d point_in_1;

  template <typename T>
  bool operator()(const T* q_12, const T* t_12, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_12);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(t_12);
    const Eigen::Quaternion<T> q_21 = q.conjugate();
    const Eigen::Matrix<T, 3, 1> t_21 = -(q_21 * t);
    const T X[3] = {T(point_in_1.x()), T(point_in_1.y()), T(point_in_1.z())};
    return residual(q_21.coeffs().data(), t_21.data(), X, r);
  }
};

}  // namespace

ceres::CostFunction* make_inverse_pose_reprojection_cost(const PinholeCamera& cam, const Eigen::Vector2d& pixel,
                                                         double inv_sigma2, const Eigen::Vector3d& point_in_1) {
  return new ceres::AutoDiffCostFunction<InversePoseResidual, 2, 4, 3>(
      new InversePoseResidual{MonoResidual{cam, pixel, std::sqrt(inv_sigma2)}, point_in_1});
}

ceres::CostFunction* make_pose_only_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m,
                                                      const Eigen::Vector3d& point_world) {
  const double sqrt_info = std::sqrt(m.inv_sigma2);
  if (m.is_stereo()) {
    using F = FixedPointResidual<StereoResidual>;
    return new ceres::AutoDiffCostFunction<F, 3, 4, 3>(new F{
        StereoResidual{cam, Eigen::Vector3d(m.pixel.x(), m.pixel.y(), m.right_x), sqrt_info}, point_world});
  }
  using F = FixedPointResidual<MonoResidual>;
  return new ceres::AutoDiffCostFunction<F, 2, 4, 3>(new F{MonoResidual{cam, m.pixel, sqrt_info}, point_world});
}

ceres::CostFunction* make_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m) {
  const double sqrt_info = std::sqrt(m.inv_sigma2);
  if (m.is_stereo()) {
    return new ceres::AutoDiffCostFunction<StereoResidual, 3, 4, 3, 3>(new StereoResidual{
        cam, Eigen::Vector3d(m.pixel.x(), m.pixel.y(), m.right_x), sqrt_info});
  }
  return new ceres::AutoDiffCostFunction<MonoResidual, 2, 4, 3, 3>(
      new MonoResidual{cam, m.pixel, sqrt_info});
}

ReprojectionCheck evaluate_reprojection(const PinholeCamera& cam, const PixelMeasurement& m,
                                        const Eigen::Quaterniond& q_cw, const Eigen::Vector3d& t_cw,
                                        const Eigen::Vector3d& point_world) {
  ReprojectionCheck check;
  const Eigen::Vector3d Xc = q_cw * point_world + t_cw;
  check.depth = Xc.z();
  if (!(Xc.z() > kMinDepth)) {
    check.chi2 = std::numeric_limits<double>::infinity();
    return check;
  }
  const Eigen::Vector2d uv = cam.project(Xc);
  double e2 = (m.pixel - uv).squaredNorm();
  if (m.is_stereo()) {
    const double du = m.right_x - (uv.x() - cam.bf / Xc.z());
    e2 += du * du;
  }
  check.chi2 = m.inv_sigma2 * e2;
  if (!std::isfinite(check.chi2)) check.chi2 = std::numeric_limits<double>::infinity();
  return check;
}

}  // namespace optimize_detail
}  // namespace edge_slam
