// Private to src/optimize: every observation of a pose-only optimisation in ONE hand-written
// Ceres residual block, with the per-observation Huber kernel applied inside it exactly as
// Ceres applies a loss to a residual block of its own.
//
// Why: with one residual block per observation, Ceres spends ~1,900 instructions per
// observation and Jacobian evaluation (autodiff Jets, per-block validity checks, the loss
// corrector, the dense Jacobian writer) on a 6-unknown problem, and tracking runs three of
// them per frame (4 rounds x up to 10 iterations each): half of the tracking CPU. One block
// pays those per-block costs once; the observations are a tight loop with analytic Jacobians.
//
// Why the result is the same: for a residual block r_i with loss rho, Ceres' cost is
// 0.5 rho(|r_i|^2) and, rho being Huber (rho'' <= 0: the first-order branch of Ceres'
// Corrector), the linear model uses sqrt(rho') r_i and sqrt(rho') J_i. PoseBatchCost writes
// exactly those corrected rows, and sums rho(|r_i|^2) as it goes. Its partner
// PairedCostLoss, the loss function of the combined block, hands that sum to Ceres as the
// block's cost with rho' = 1, rho'' = 0, for which Ceres' own correction is a multiplication
// by 1. So cost, gradient and Gauss-Newton model are the per-observation ones, summed in
// another order: the iterates agree up to floating-point rounding (test_optimize_pose_batch).
// Observations sitting out a round are inactive: zero rows, no cost, as if absent.
//
// Square-root form (the default): Ceres' trust-region step, its model cost change, Jacobi
// scaling and gradient depend on the Jacobian J and residuals r only through J^T J and J^T r
// (DENSE_NORMAL_CHOLESKY solves the normal equations; model change = -(J d).(r + J d / 2)).
// So instead of ~900 rows the block hands Ceres 7 rows (S, r') with S^T S = J^T J and
// S^T r' = J^T r, from a pivoted LDL^T of the normal matrix: the same steps, without
// Ceres' per-row work (validity checks, column scaling, the manifold product, the dense
// Jacobian copy and product), which was half the cost of a solve. The block's cost is still
// the per-observation robust sum (PairedCostLoss), not |r'|^2 / 2.
// The normal matrix is accumulated in the quaternion manifold's tangent space (6 x 6, upper
// triangle, each point rotated by one 3 x 3 matrix) and S's quaternion columns are mapped back
// through the manifold's plus-Jacobian M (S_rot M^T, which Ceres multiplies by M again: M^T M
// = I): J M, the Jacobian Ceres solves with, is unchanged, at about half the arithmetic per
// observation of the 7 x 7 ambient form. So the square-root form gives q only through
// EigenQuaternionManifold, the manifold every caller sets on it.
#pragma once
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <vector>

#include "edge_slam/camera/pinhole_camera.h"
#include "reprojection_cost.h"

namespace edge_slam {
namespace optimize_detail {

class PoseBatchCost : public ceres::CostFunction {
 public:
  // kRows: 3 residual rows per stereo observation, 2 per monocular one, in the order given
  // (the per-observation rows, for tests); kSquareRoot: 7 rows as explained above.
  enum class Form { kRows, kSquareRoot };
  static constexpr int kSquareRootRows = 7;

  // Parameters: quaternion (x, y, z, w) [4] and translation [3] of T_cw.
  PoseBatchCost(const PinholeCamera& cam, const std::vector<PixelMeasurement>& measurements,
                const std::vector<Eigen::Vector3d>& points_world, Form form = Form::kSquareRoot);

  // Which observations take part (default: all), and whether the Huber kernel applies
  // (delta sqrt(5.991) mono, sqrt(7.815) stereo, as the per-observation version).
  void set_active(size_t i, bool active) { active_[i] = active; }
  void set_robust(bool robust) { robust_ = robust; }
  size_t size() const { return obs_.size(); }

  // Fails (as the per-observation residual would) when an active point is not in front.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  // Sum over active observations of rho(|r_i|^2) (plain |r_i|^2 when not robust) at the last
  // Evaluate: the combined block's cost, read by PairedCostLoss.
  double last_robust_sum() const { return robust_sum_; }

 private:
  struct Observation {
    Eigen::Vector3d point;
    Eigen::Vector3d measured;  // u, v, u_right (unused when monocular)
    double sqrt_info;
    bool stereo;
    int first_row;
  };
  // The observation's loss added to *sum; returns the factor its rows are scaled by.
  double add_loss(double squared_norm, bool stereo, double* sum) const;
  bool evaluate_rows(double const* const* parameters, double* residuals, double** jacobians) const;
  bool evaluate_square_root(double const* const* parameters, double* residuals, double** jacobians) const;
  // S, r' of the square-root form from the tangent-space A and g into Ceres' ambient arrays.
  void write_square_root(const Eigen::Matrix<double, 6, 6>& A, const Eigen::Matrix<double, 6, 1>& g,
                         const double* quaternion, double* residuals, double** jacobians) const;

  double fx_, fy_, cx_, cy_, bf_;
  Form form_;
  std::vector<Observation> obs_;
  std::vector<char> active_;
  bool robust_ = true;
  double huber_delta_mono_, huber_delta_stereo_;  // ceres::HuberLoss(delta), evaluated inline
  ceres::EigenQuaternionManifold quaternion_manifold_;  // the manifold the optimisers give q
  mutable double robust_sum_ = 0.0;
};

// The loss of the combined block: its cost is what PoseBatchCost summed, per observation.
class PairedCostLoss : public ceres::LossFunction {
 public:
  explicit PairedCostLoss(const PoseBatchCost& cost) : cost_(cost) {}
  void Evaluate(double /*squared_norm*/, double rho[3]) const override {
    rho[0] = cost_.last_robust_sum();
    rho[1] = 1.0;
    rho[2] = 0.0;
  }

 private:
  const PoseBatchCost& cost_;
};

}  // namespace optimize_detail
}  // namespace edge_slam
