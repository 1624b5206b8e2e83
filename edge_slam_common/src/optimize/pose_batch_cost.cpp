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
  const double vx = parameters[0][0], vy = parameters[0][1], vz = parameters[0][2], w = parameters[0][3];
  const double tx = parameters[1][0], ty = parameters[1][1], tz = parameters[1][2];
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
    const double X = o.point.x(), Y = o.point.y(), Z = o.point.z();
    const double cx = vy * Z - vz * Y, cy = vz * X - vx * Z, cz = vx * Y - vy * X;  // v x X
    const double ccx = vy * cz - vz * cy, ccy = vz * cx - vx * cz, ccz = vx * cy - vy * cx;  // v x (v x X)
    const double xc = X + 2.0 * w * cx + 2.0 * ccx + tx;
    const double yc = Y + 2.0 * w * cy + 2.0 * ccy + ty;
    const double zc = Z + 2.0 * w * cz + 2.0 * ccz + tz;
    if (!(zc > kMinDepth)) return false;
    const double inv_z = 1.0 / zc;
    const double u = fx_ * xc * inv_z + cx_;
    const double vv = fy_ * yc * inv_z + cy_;
    r[0] = o.sqrt_info * (o.measured.x() - u);
    r[1] = o.sqrt_info * (o.measured.y() - vv);
    if (o.stereo) r[2] = o.sqrt_info * (o.measured.z() - (u - bf_ * inv_z));
    double s = r[0] * r[0] + r[1] * r[1];
    if (o.stereo) s += r[2] * r[2];
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
      // Row k of d r / d Xc (= d r / d t): -sqrt_info * d projection_k / d Xc, times the loss scale.
      const double kk = -o.sqrt_info * scale;
      const double a = kk * fx_ * inv_z, b = kk * fy_ * inv_z, c = -kk * fx_ * xc * inv_z * inv_z;
      const double d = -kk * fy_ * yc * inv_z * inv_z, e = kk * bf_ * inv_z * inv_z;
      const double rows[3][3] = {{a, 0.0, c}, {0.0, b, d}, {a, 0.0, c + e}};
      const double vX = vx * X + vy * Y + vz * Z;
      for (int k = 0; k < n; ++k) {
        const double* g = rows[k];
        if (jt) {
          double* J = jt + 3 * (o.first_row + k);
          J[0] = g[0];
          J[1] = g[1];
          J[2] = g[2];
        }
        if (jq) {
          // g^T d Xc / d(v, w), with d Xc / dv = -2w [X]x + 2 (v.X I + v X^T - 2 X v^T) and
          // d Xc / dw = 2 v x X, i.e. -2w (g x X) + 2 (v.X) g + 2 (g.v) X - 4 (g.X) v and 2 g.(v x X).
          const double gv = g[0] * vx + g[1] * vy + g[2] * vz, gX = g[0] * X + g[1] * Y + g[2] * Z;
          const double gxX0 = g[1] * Z - g[2] * Y, gxX1 = g[2] * X - g[0] * Z, gxX2 = g[0] * Y - g[1] * X;
          double* J = jq + 4 * (o.first_row + k);
          J[0] = -2.0 * w * gxX0 + 2.0 * vX * g[0] + 2.0 * gv * X - 4.0 * gX * vx;
          J[1] = -2.0 * w * gxX1 + 2.0 * vX * g[1] + 2.0 * gv * Y - 4.0 * gX * vy;
          J[2] = -2.0 * w * gxX2 + 2.0 * vX * g[2] + 2.0 * gv * Z - 4.0 * gX * vz;
          J[3] = 2.0 * (g[0] * cx + g[1] * cy + g[2] * cz);
        }
      }
    }
    for (int k = 0; k < n; ++k) r[k] *= scale;
  }
  robust_sum_ = sum;
  return true;
}

}  // namespace optimize_detail
}  // namespace edge_slam
