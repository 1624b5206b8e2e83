// Private to src/optimize: the reprojection residuals shared by pose-only optimisation and
// bundle adjustment. The AutoDiff templates are instantiated once, in reprojection_cost.cpp,
// so the other optimisers only see plain CostFunction pointers (Ceres templates compile slowly).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/cost_function.h>

#include "edge_slam/camera/pinhole_camera.h"

namespace edge_slam {
namespace optimize_detail {

// Chi-square thresholds at 95% for 2 (monocular) and 3 (stereo-projected) degrees of freedom.
constexpr double kChi2Mono = 5.991;
constexpr double kChi2Stereo = 7.815;

// One keypoint measurement of a 3D point. right_x < 0 selects the monocular (u, v) term,
// otherwise the stereo-projected (u, v, u_right) term with u_right = u - bf / z.
struct PixelMeasurement {
  Eigen::Vector2d pixel;
  double right_x = -1.0;
  double inv_sigma2 = 1.0;
  bool is_stereo() const { return right_x >= 0.0; }
  double chi2_threshold() const { return is_stereo() ? kChi2Stereo : kChi2Mono; }
};

// Residual blocks take parameters (quaternion xyzw [4], translation [3], point_world [3]) for
// the pose T_cw = (q, t). Residuals are whitened by sqrt(inv_sigma2), so their squared norm is chi2.
// Always three residuals (the monocular term's third is a constant 0), see reprojection_cost.cpp.
ceres::CostFunction* make_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m);
// The same residual by automatic differentiation: the reference the analytic Jacobians are tested against.
ceres::CostFunction* make_reprojection_cost_autodiff(const PinholeCamera& cam, const PixelMeasurement& m);

// Same residual over (quaternion [4], translation [3]) only, the point being a known constant.
ceres::CostFunction* make_pose_only_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m,
                                                      const Eigen::Vector3d& point_world);

// Residual over the parameters (q_12 [4], t_12 [3]) of T_12, for a point known in frame 1 and
// observed in frame 2 (through T_12^-1): monocular, or stereo-projected when m.right_x >= 0.
// Used by the relative-pose refinement.
ceres::CostFunction* make_inverse_pose_reprojection_cost(const PinholeCamera& cam, const PixelMeasurement& m,
                                                         const Eigen::Vector3d& point_in_1);

struct ReprojectionCheck {
  double chi2 = 0.0;
  double depth = 0.0;  // z of the point in the camera frame
};

// Points closer than this (or behind the camera) cannot be projected; the residuals refuse them.
constexpr double kMinDepth = 1e-6;

// Plain-double evaluation of the same residual, for the inlier/outlier classification.
ReprojectionCheck evaluate_reprojection(const PinholeCamera& cam, const PixelMeasurement& m,
                                        const Eigen::Quaterniond& q_cw, const Eigen::Vector3d& t_cw,
                                        const Eigen::Vector3d& point_world);

// An observation is an outlier when the point is behind the camera or chi2 exceeds the threshold.
inline bool is_reprojection_outlier(const ReprojectionCheck& c, const PixelMeasurement& m) {
  return !(c.depth > kMinDepth) || !(c.chi2 <= m.chi2_threshold());
}

}  // namespace optimize_detail
}  // namespace edge_slam
