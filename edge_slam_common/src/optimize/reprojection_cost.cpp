#include "reprojection_cost.h"

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

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

// Residual of a point known in frame 1 observed in frame 2, for the pose T_12: the point is
// mapped by T_21 = T_12^-1 (quaternion conjugate, t_21 = -(q_21 * t_12)).
template <typename Residual>
struct InversePoseResidual {
  Residual residual;
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

// The monocular residual with a constant zero third row. Bundle adjustment gives every
// observation three rows so that Ceres sees one row-block size and uses its specialised
// (3, 3, 3) Schur eliminator; mixing 2- and 3-row blocks falls back to the generic one.
struct PaddedMonoResidual {
  MonoResidual residual;

  template <typename T>
  bool operator()(const T* q, const T* t, const T* X, T* r) const {
    r[2] = T(0.0);
    return residual(q, t, X, r);
  }
};

// The bundle adjustment residual with hand-written Jacobians: BA evaluates it ~10^5 times
// per keyframe, and the autodiff version spent more time in the Jet arithmetic than Ceres
// spent solving. Same value as StereoResidual / PaddedMonoResidual (checked in
// test_optimize_reprojection_cost), including the rotation formula of Eigen's q * X,
//   f(q, X) = X + 2w (v x X) + 2 v x (v x X),  q = (v, w),
// whose derivative in the ambient (x, y, z, w) coordinates Ceres' quaternion manifold expects.
class AnalyticReprojectionCost : public ceres::SizedCostFunction<3, 4, 3, 3> {
 public:
  AnalyticReprojectionCost(const PinholeCamera& cam, const PixelMeasurement& m)
      : fx_(cam.fx), fy_(cam.fy), cx_(cam.cx), cy_(cam.cy), bf_(cam.bf),
        measured_(m.pixel.x(), m.pixel.y(), m.right_x), stereo_(m.is_stereo()), sqrt_info_(std::sqrt(m.inv_sigma2)) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Map<const Eigen::Vector3d> v(parameters[0]);
    const double w = parameters[0][3];
    const Eigen::Map<const Eigen::Vector3d> t(parameters[1]);
    const Eigen::Map<const Eigen::Vector3d> X(parameters[2]);
    const Eigen::Vector3d vxX = v.cross(X);
    const Eigen::Vector3d Xc = X + 2.0 * w * vxX + 2.0 * v.cross(vxX) + t;
    if (!(Xc.z() > kMinDepth)) return false;
    const double inv_z = 1.0 / Xc.z();
    const double u = fx_ * Xc.x() * inv_z + cx_;
    const double vv = fy_ * Xc.y() * inv_z + cy_;
    residuals[0] = sqrt_info_ * (measured_.x() - u);
    residuals[1] = sqrt_info_ * (measured_.y() - vv);
    residuals[2] = stereo_ ? sqrt_info_ * (measured_.z() - (u - bf_ * inv_z)) : 0.0;
    if (jacobians == nullptr) return true;

    // d residual / d Xc = -sqrt_info * d projection / d Xc (third row zero for monocular).
    Eigen::Matrix3d dr_dXc;
    const double inv_z2 = inv_z * inv_z;
    dr_dXc << fx_ * inv_z, 0.0, -fx_ * Xc.x() * inv_z2,
              0.0, fy_ * inv_z, -fy_ * Xc.y() * inv_z2,
              fx_ * inv_z, 0.0, -fx_ * Xc.x() * inv_z2 + bf_ * inv_z2;
    if (!stereo_) dr_dXc.row(2).setZero();
    dr_dXc *= -sqrt_info_;

    using RowMajor34 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
    using RowMajor33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    if (jacobians[0] != nullptr) {
      Eigen::Matrix<double, 3, 4> dXc_dq;
      const double vX = v.dot(X);
      dXc_dq.leftCols<3>() = -2.0 * w * skew(X) +
                             2.0 * (vX * Eigen::Matrix3d::Identity() + v * X.transpose() - 2.0 * X * v.transpose());
      dXc_dq.col(3) = 2.0 * vxX;
      Eigen::Map<RowMajor34> J(jacobians[0]);
      J = dr_dXc * dXc_dq;
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<RowMajor33> J(jacobians[1]);
      J = dr_dXc;
    }
    if (jacobians[2] != nullptr) {
      const Eigen::Matrix3d V = skew(v);
      const Eigen::Matrix3d dXc_dX = Eigen::Matrix3d::Identity() + 2.0 * w * V + 2.0 * V * V;
      Eigen::Map<RowMajor33> J(jacobians[2]);
      J = dr_dXc * dXc_dX;
    }
    return true;
  }

 private:
  static Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
    Eigen::Matrix3d S;
    S << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    return S;
  }

  double fx_, fy_, cx_, cy_, bf_;
  Eigen::Vector3d measured_;  // u, v, u_right (u_right unused when monocular)
  bool stereo_;
  double sqrt_info_;
};

// A (quaternion [4], translation [3]) cost of one measurement of a known point, the residual
// wrapped by `Wrapper` (FixedPointResidual: T_cw; InversePoseResidual: T_12 of a point of frame 1).
template <template <typename> class Wrapper>
ceres::CostFunction* make_pose_parameter_cost(const PinholeCamera& cam, const PixelMeasurement& m,
                                              const Eigen::Vector3d& point) {
  const double sqrt_info = std::sqrt(m.inv_sigma2);
  if (m.is_stereo()) {
    using F = Wrapper<StereoResidual>;
    return new ceres::AutoDiffCostFunction<F, 3, 4, 3>(
        new F{StereoResidual{cam, Eigen::Vector3d(m.pixel.x(), m.pixel.y(), m.right_x), sqrt_info}, point});
  }
  using F = Wrapper<MonoResidual>;
  return new ceres::AutoDiffCostFunction<F, 2, 4, 3>(new F{MonoResidual{cam, m.pixel, sqrt_info}, point});
}

}  // namespace

ceres::CostFunction* make_inverse_pose_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m,
                                                         const Eigen::Vector3d& point_in_1) {
  return make_pose_parameter_cost<InversePoseResidual>(cam, m, point_in_1);
}

ceres::CostFunction* make_pose_only_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m,
                                                      const Eigen::Vector3d& point_world) {
  return make_pose_parameter_cost<FixedPointResidual>(cam, m, point_world);
}

ceres::CostFunction* make_reprojection_cost_autodiff(const PinholeCamera& cam, const PixelMeasurement& m) {
  const double sqrt_info = std::sqrt(m.inv_sigma2);
  if (m.is_stereo()) {
    return new ceres::AutoDiffCostFunction<StereoResidual, 3, 4, 3, 3>(new StereoResidual{
        cam, Eigen::Vector3d(m.pixel.x(), m.pixel.y(), m.right_x), sqrt_info});
  }
  return new ceres::AutoDiffCostFunction<PaddedMonoResidual, 3, 4, 3, 3>(
      new PaddedMonoResidual{MonoResidual{cam, m.pixel, sqrt_info}});
}

ceres::CostFunction* make_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m) {
  return new AnalyticReprojectionCost(cam, m);
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
