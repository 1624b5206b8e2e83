#include "pose_batch_cost.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

namespace edge_slam {
namespace optimize_detail {

PoseBatchCost::PoseBatchCost(const PinholeCamera& cam, const std::vector<PixelMeasurement>& measurements,
                             const std::vector<Eigen::Vector3d>& points_world, Form form)
    : fx_(cam.fx), fy_(cam.fy), cx_(cam.cx), cy_(cam.cy), bf_(cam.bf),
      form_(form),
      active_(measurements.size(), 1),
      huber_delta_mono_(std::sqrt(kChi2Mono)),
      huber_delta_stereo_(std::sqrt(kChi2Stereo)) {
  int rows = 0;
  obs_.reserve(measurements.size());
  for (size_t i = 0; i < measurements.size(); ++i) {
    const PixelMeasurement& m = measurements[i];
    obs_.push_back(Observation{points_world[i], Eigen::Vector3d(m.pixel.x(), m.pixel.y(), m.right_x),
                               std::sqrt(m.inv_sigma2), m.is_stereo(), rows});
    rows += m.is_stereo() ? 3 : 2;
  }
  set_num_residuals(form_ == Form::kRows ? rows : kSquareRootRows);
  mutable_parameter_block_sizes()->assign({4, 3});
}

double PoseBatchCost::add_loss(double squared_norm, bool stereo, double* sum) const {
  if (!robust_) {
    *sum += squared_norm;
    return 1.0;
  }
  // ceres::HuberLoss::Evaluate, inline (it is a library call per observation otherwise), and
  // Ceres' first-order correction (Huber: rho'' <= 0): the rows are scaled by sqrt(rho').
  const double delta = stereo ? huber_delta_stereo_ : huber_delta_mono_;
  if (squared_norm <= delta * delta) {
    *sum += squared_norm;
    return 1.0;
  }
  const double root = std::sqrt(squared_norm);
  *sum += 2.0 * delta * root - delta * delta;
  return std::sqrt(std::max(std::numeric_limits<double>::min(), delta / root));
}

bool PoseBatchCost::evaluate_rows(double const* const* parameters, double* residuals, double** jacobians) const {
  const double vx = parameters[0][0], vy = parameters[0][1], vz = parameters[0][2], w = parameters[0][3];
  const double tx = parameters[1][0], ty = parameters[1][1], tz = parameters[1][2];
  // The point is rotated as in evaluate_square_root (one matrix), so both forms give the same
  // residuals and cost to the bit; the quaternion formula below is only for the Jacobian.
  const Eigen::Matrix3d R = Eigen::Map<const Eigen::Quaterniond>(parameters[0]).toRotationMatrix();
  const bool want_jacobian = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
  double sum = 0.0;
  for (size_t i = 0; i < obs_.size(); ++i) {
    const Observation& o = obs_[i];
    const int n = o.stereo ? 3 : 2;
    double r[3] = {0.0, 0.0, 0.0};
    double J[3][7] = {};
    if (active_[i]) {
      const double X = o.point.x(), Y = o.point.y(), Z = o.point.z();
      const double cx = vy * Z - vz * Y, cy = vz * X - vx * Z, cz = vx * Y - vy * X;  // v x X
      const Eigen::Vector3d Xr = R * o.point;
      const double xc = Xr.x() + tx, yc = Xr.y() + ty, zc = Xr.z() + tz;
      if (!(zc > kMinDepth)) return false;
      const double inv_z = 1.0 / zc;
      const double u = fx_ * xc * inv_z + cx_;
      const double vv = fy_ * yc * inv_z + cy_;
      r[0] = o.sqrt_info * (o.measured.x() - u);
      r[1] = o.sqrt_info * (o.measured.y() - vv);
      if (o.stereo) r[2] = o.sqrt_info * (o.measured.z() - (u - bf_ * inv_z));
      const double s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
      const double scale = add_loss(s, o.stereo, &sum);
      for (int k = 0; k < n; ++k) r[k] *= scale;
      if (want_jacobian) {
        // Row k of d r / d Xc (= d r / d t): -sqrt_info * d projection_k / d Xc, times the loss scale.
        const double kk = -o.sqrt_info * scale;
        const double a = kk * fx_ * inv_z, b = kk * fy_ * inv_z, c = -kk * fx_ * xc * inv_z * inv_z;
        const double d = -kk * fy_ * yc * inv_z * inv_z, e = kk * bf_ * inv_z * inv_z;
        const double rows[3][3] = {{a, 0.0, c}, {0.0, b, d}, {a, 0.0, c + e}};
        const double vX = vx * X + vy * Y + vz * Z;
        for (int k = 0; k < n; ++k) {
          const double* gr = rows[k];
          // gr^T d Xc / d(v, w), with d Xc / dv = -2w [X]x + 2 (v.X I + v X^T - 2 X v^T) and
          // d Xc / dw = 2 v x X, i.e. -2w (gr x X) + 2 (v.X) gr + 2 (gr.v) X - 4 (gr.X) v and 2 gr.(v x X).
          const double gv = gr[0] * vx + gr[1] * vy + gr[2] * vz, gX = gr[0] * X + gr[1] * Y + gr[2] * Z;
          const double gxX0 = gr[1] * Z - gr[2] * Y, gxX1 = gr[2] * X - gr[0] * Z, gxX2 = gr[0] * Y - gr[1] * X;
          J[k][0] = -2.0 * w * gxX0 + 2.0 * vX * gr[0] + 2.0 * gv * X - 4.0 * gX * vx;
          J[k][1] = -2.0 * w * gxX1 + 2.0 * vX * gr[1] + 2.0 * gv * Y - 4.0 * gX * vy;
          J[k][2] = -2.0 * w * gxX2 + 2.0 * vX * gr[2] + 2.0 * gv * Z - 4.0 * gX * vz;
          J[k][3] = 2.0 * (gr[0] * cx + gr[1] * cy + gr[2] * cz);
          J[k][4] = gr[0];
          J[k][5] = gr[1];
          J[k][6] = gr[2];
        }
      }
    }
    for (int k = 0; k < n; ++k) {  // inactive observations: zero rows
      residuals[o.first_row + k] = r[k];
      if (jacobians && jacobians[0])
        for (int c = 0; c < 4; ++c) jacobians[0][4 * (o.first_row + k) + c] = J[k][c];
      if (jacobians && jacobians[1])
        for (int c = 0; c < 3; ++c) jacobians[1][3 * (o.first_row + k) + c] = J[k][4 + c];
    }
  }
  robust_sum_ = sum;
  return true;
}

bool PoseBatchCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  return form_ == Form::kRows ? evaluate_rows(parameters, residuals, jacobians)
                              : evaluate_square_root(parameters, residuals, jacobians);
}

bool PoseBatchCost::evaluate_square_root(double const* const* parameters, double* residuals,
                                         double** jacobians) const {
  const Eigen::Map<const Eigen::Quaterniond> q(parameters[0]);
  const Eigen::Map<const Eigen::Vector3d> t(parameters[1]);
  // Eigen's q * X is R(q) X for a unit quaternion: one matrix for all points instead of the
  // quaternion formula per point.
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const bool want_jacobian = jacobians != nullptr && (jacobians[0] != nullptr || jacobians[1] != nullptr);
  // Normal equations in the manifold's tangent space (d rotation, d t): Ceres' quaternion
  // manifold perturbs q as exp(delta) * q, which turns R X by 2 delta, so a row g^T of
  // d r / d Xc has d r / d delta = 2 (R X x g)^T and d r / d t = g^T. Upper triangle only.
  double A[6][6] = {};
  double b[6] = {};
  double sum = 0.0;
  for (size_t i = 0; i < obs_.size(); ++i) {
    if (!active_[i]) continue;
    const Observation& o = obs_[i];
    const Eigen::Vector3d Xr = R * o.point;
    const double xc = Xr.x() + t.x(), yc = Xr.y() + t.y(), zc = Xr.z() + t.z();
    if (!(zc > kMinDepth)) return false;
    const double inv_z = 1.0 / zc;
    const double u = fx_ * xc * inv_z + cx_;
    const double vv = fy_ * yc * inv_z + cy_;
    double r[3];
    r[0] = o.sqrt_info * (o.measured.x() - u);
    r[1] = o.sqrt_info * (o.measured.y() - vv);
    r[2] = o.stereo ? o.sqrt_info * (o.measured.z() - (u - bf_ * inv_z)) : 0.0;
    const double s = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    const double scale = add_loss(s, o.stereo, &sum);
    if (!want_jacobian) continue;
    const int n = o.stereo ? 3 : 2;
    const double kk = -o.sqrt_info * scale;
    const double a = kk * fx_ * inv_z, bb = kk * fy_ * inv_z, c = -kk * fx_ * xc * inv_z * inv_z;
    const double d = -kk * fy_ * yc * inv_z * inv_z, e = kk * bf_ * inv_z * inv_z;
    const double rows[3][3] = {{a, 0.0, c}, {0.0, bb, d}, {a, 0.0, c + e}};
    for (int k = 0; k < n; ++k) {
      const double* g = rows[k];
      const double J[6] = {2.0 * (Xr.y() * g[2] - Xr.z() * g[1]), 2.0 * (Xr.z() * g[0] - Xr.x() * g[2]),
                           2.0 * (Xr.x() * g[1] - Xr.y() * g[0]), g[0], g[1], g[2]};
      const double rk = scale * r[k];
      for (int p = 0; p < 6; ++p) {
        b[p] += J[p] * rk;
        for (int m = p; m < 6; ++m) A[p][m] += J[p] * J[m];
      }
    }
  }
  robust_sum_ = sum;
  if (!want_jacobian) {  // a cost-only evaluation: Ceres reads the cost, not these rows
    std::fill(residuals, residuals + kSquareRootRows, 0.0);
    return true;
  }
  Eigen::Matrix<double, 6, 6> A6;
  for (int p = 0; p < 6; ++p)
    for (int m = p; m < 6; ++m) A6(p, m) = A6(m, p) = A[p][m];
  write_square_root(A6, Eigen::Map<const Eigen::Matrix<double, 6, 1>>(b), parameters[0], residuals, jacobians);
  return true;
}

void PoseBatchCost::write_square_root(const Eigen::Matrix<double, 6, 6>& A, const Eigen::Matrix<double, 6, 1>& g,
                                      const double* quaternion, double* residuals, double** jacobians) const {
  // A = P^T L D L^T P (pivoted LDL^T: A is only semi-definite). S = D^1/2 L^T P gives
  // S^T S = A, and r' = D^-1/2 L^-1 P g gives S^T r' = g (g = J^T r lies in A's range).
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(A);
  const Eigen::PermutationMatrix<6> P(ldlt.transpositionsP());
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>(ldlt.matrixU()) * P;  // L^T P
  Eigen::Matrix<double, 6, 1> y = P * g;                                               // P g
  ldlt.matrixL().solveInPlace(y);                                                      // L^-1 P g
  const Eigen::Matrix<double, 6, 1> D = ldlt.vectorD();
  for (int i = 0; i < 6; ++i) {
    // A pivot that rounding left at or below zero belongs to a direction the rows do not
    // constrain: an empty row (its share of g is rounding noise too).
    const double d = D[i] > 1e-300 ? std::sqrt(D[i]) : 0.0;
    S.row(i) *= d;
    residuals[i] = d > 0.0 ? y[i] / d : 0.0;
  }
  residuals[6] = 0.0;  // the seventh row is empty: the block keeps a fixed size
  // Back to the ambient quaternion: Ceres multiplies the quaternion columns by the manifold's
  // plus-Jacobian M (4 x 3, orthonormal columns for a unit quaternion), so rows S_rot M^T give
  // back S_rot. Row 7 is zero.
  if (jacobians[0]) {
    double M[12];
    quaternion_manifold_.PlusJacobian(quaternion, M);  // row-major 4 x 3
    for (int i = 0; i < 6; ++i)
      for (int c = 0; c < 4; ++c)
        jacobians[0][4 * i + c] = S(i, 0) * M[3 * c] + S(i, 1) * M[3 * c + 1] + S(i, 2) * M[3 * c + 2];
    std::fill(jacobians[0] + 24, jacobians[0] + 28, 0.0);
  }
  if (jacobians[1]) {
    for (int i = 0; i < 6; ++i)
      for (int c = 0; c < 3; ++c) jacobians[1][3 * i + c] = S(i, 3 + c);
    std::fill(jacobians[1] + 18, jacobians[1] + 21, 0.0);
  }
}

}  // namespace optimize_detail
}  // namespace edge_slam
