// Pose-only optimisation (motion-only bundle adjustment) of one camera against known 3D points,
// following the ORB-SLAM2 PoseOptimization recipe: 4 rounds of 10 Levenberg-Marquardt
// iterations; after each round every observation is re-classified by its chi2 and outliers sit
// out the next round; the Huber kernel is dropped in the last round.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "edge_slam/camera/pinhole_camera.h"

namespace edge_slam {

struct PoseObservation {
  Eigen::Vector3d point_world;
  Eigen::Vector2d pixel;  // undistorted keypoint
  double right_x = -1.0;  // virtual right coordinate (u - bf/z); < 0 => monocular term
  double inv_sigma2 = 1.0;  // 1 / sigma^2 of the keypoint's pyramid level
};

struct PoseOptimizationResult {
  bool ok = false;
  int inliers = 0;  // observations not flagged in is_outlier after the last round
  std::string message;
};

struct PoseOptimizationOptions {
  int rounds = 4;
  int iterations_per_round = 10;
  int min_observations = 3;  // usable (finite) observations required to attempt the solve
};

// Refines T_cw (x_c = T_cw * x_w) in place, starting from its current value.
// is_outlier is in/out and resized to obs.size() if needed: observations flagged true on input
// sit out the first round but, like every observation, are re-tested after each round.
// Observations with non-finite data are always outliers. Chi2 thresholds: 5.991 (mono),
// 7.815 (stereo); points at or behind the camera are outliers.
// ok=false (T_cw and is_outlier untouched) when fewer than min_observations usable observations,
// a non-finite initial pose, or a numerical failure. ok=true with few inliers is possible: the
// caller judges the inlier count, as ORB-SLAM2's tracking does.
PoseOptimizationResult optimize_pose(const PinholeCamera& cam,
                                     const std::vector<PoseObservation>& obs,
                                     Eigen::Isometry3d& T_cw, std::vector<bool>& is_outlier,
                                     const PoseOptimizationOptions& options = {});

}  // namespace edge_slam
