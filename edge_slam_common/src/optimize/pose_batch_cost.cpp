#include "pose_batch_cost.h"

#include <algorithm>
#include <cmath>

namespace edge_slam {
namespace optimize_detail {

PoseBatchCost::PoseBatchCost(const PinholeCamera& cam, const std::vector<PixelMeasurement>& measurements,
                             const std::vector<Eigen::Vector3d>& points_world)
    : fx_(cam.fx), fy_(cam.fy), cx_(cam.cx), cy_(cam.cy), bf_(cam.bf),
      active_(measurements.size(), 1),
      huber_mono_(std::sqrt(kChi2Mono)),
      huber_stereo_(std::sqrt(kChi2Stereo)) {
  int rows = 0;
  obs_.reserve(measurements.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    const PixelMeasurement& m = measurements[i];
    obs_.push_back(Observation{points_world[i], Eigen::Vector3d(m.pixel.x(), m.pixel.y(), m.right_x),
                               std::sqrt(m.inv_sigma2), m.is_stereo(), rows});
    rows += m.is_stereo() ? 3 : 2;
  }
  set_num_residuals(rows);
  mutable_parameter_block_sizes()->assign({4, 3});
}

bool PoseBatchCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> v(parameters[0]);
  const double w = parameters[0][3];
  const Eigen::Map<const Eigen::Vector3d> t(parameters[1]);
  double* const jq = jacobians ? jacobians[0] : nullptr;  // row-major rows x 4
  double* const jt = jacobians ? jacobians[1] : nullptr;  // row-major rows x 3
  double sum = 0.0;
  for (size_t i = 0; i < obs_.size(); ++i) {
    const Observation& o = obs_[i];
    const int n = o.stereo ? 3 : 2;
    double* r = residuals + o.first_row;
    if (!active_[i]) {
      for (int k = 0; k < n; ++k) r[k] = 0.0;
      if (jq) std::fill(jq + 4 * o.first_row, jq + 4 * (o.first_row + n), 0.0);
      if (jt) std::fill(jt + 3 * o.first_row, jt + 3 * (o.first_row + n), 0.0);
      continue;
    }
    // Eigen's q * X for a unit quaternion q = (v, w): X + 2w (v x X) + 2 v x (v x X).
    const Eigen::Vector3d& X = o.point;
    const Eigen::Vector3d vxX = v.cross(X);
    const Eigen::Vector3d Xc = X + 2.0 * w * vxX + 2.0 * v.cross(vxX) + t;
    if (!(Xc.z() > kMinDepth)) return false;
    const double inv_z = 1.0 / Xc.z();
    const double u = fx_ * Xc.x() * inv_z + cx_;
    const double vv = fy_ * Xc.y() * inv_z + cy_;
    r[0] = o.sqrt_info * (o.measured.x() - u);
    r[1] = o.sqrt_info * (o.measured.y() - vv);
    if (o.stereo) r[2] = o.sqrt_info * (o.measured.z() - (u - bf_ * inv_z));
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += r[k] * r[k];
    // The per-observation loss and Ceres' first-order correction (Huber: rho'' <= 0).
    double scale = 1.0;
    if (robust_) {
      double rho[3];
      (o.stereo ? huber_stereo_ : huber_mono_).Evaluate(s, rho);
      sum += rho[0];
      scale = std::sqrt(rho[1]);
    } else {
      sum += s;
    }
    if (jq || jt) {
      // d r / d Xc = -sqrt_info * d projection / d Xc, times the loss scale.
      const double inv_z2 = inv_z * inv_z;
      const double k = -o.sqrt_info * scale;
      Eigen::Matrix3d dr_dXc;
      dr_dXc << fx_ * inv_z, 0.0, -fx_ * Xc.x() * inv_z2,
                0.0, fy_ * inv_z, -fy_ * Xc.y() * inv_z2,
                fx_ * inv_z, 0.0, -fx_ * Xc.x() * inv_z2 + bf_ * inv_z2;
      dr_dXc *= k;
      if (jq) {
        // d Xc / d (v, w) of the rotation formula above, in the ambient (x, y, z, w) order.
        Eigen::Matrix<double, 3, 4> dXc_dq;
        const double vX = v.dot(X);
        Eigen::Matrix3d skew_X;
        skew_X << 0.0, -X.z(), X.y(), X.z(), 0.0, -X.x(), -X.y(), X.x(), 0.0;
        dXc_dq.leftCols<3>() = -2.0 * w * skew_X +
                               2.0 * (vX * Eigen::Matrix3d::Identity() + v * X.transpose() - 2.0 * X * v.transpose());
        dXc_dq.col(3) = 2.0 * vxX;
        const Eigen::Matrix<double, 3, 4> J = dr_dXc * dXc_dq;
        for (int row = 0; row < n; ++row)
          for (int c = 0; c < 4; ++c) jq[4 * (o.first_row + row) + c] = J(row, c);
      }
      if (jt)
        for (int row = 0; row < n; ++row)
          for (int c = 0; c < 3; ++c) jt[3 * (o.first_row + row) + c] = dr_dXc(row, c);
    }
    for (int k = 0; k < n; ++k) r[k] *= scale;
  }
  robust_sum_ = sum;
  return true;
}

}  // namespace optimize_detail
}  // namespace edge_slam
