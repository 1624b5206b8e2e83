// Camera pose from 2D-3D correspondences (relocalization): OpenCV's RANSAC PnP with the EPnP
// minimal solver, then pose-only optimisation (optimize_pose) seeded with the RANSAC inliers,
// which also brings in the stereo-projected terms of RGB-D keypoints.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "edge_slam/camera/pinhole_camera.h"
#include "edge_slam/optimize/pose_optimizer.h"

namespace edge_slam {

struct PnpParams {
  double ransac_reprojection_px = 2.5;  // ~sqrt(5.991): the level-0 chi2 threshold in pixels
  int ransac_iterations = 300;
  double ransac_confidence = 0.99;
  int min_inliers = 10;  // accepted only with at least this many inliers after refinement
  bool refine = true;    // run optimize_pose on the RANSAC result
};

struct PnpResult {
  bool ok = false;
  std::string message;
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();  // x_c = T_cw * x_w
  std::vector<bool> inliers;  // per correspondence
  int num_inliers = 0;
};

// Each PoseObservation is one correspondence (point_world <-> undistorted pixel). The camera
// model is pinhole without distortion (pixels are undistorted). ok=false with a message when
// fewer than 6 finite correspondences, RANSAC finds no model, refinement fails, or the inliers
// stay below min_inliers; T_cw then holds the best estimate found (identity if none).
PnpResult solve_pnp_ransac(const PinholeCamera& cam, const std::vector<PoseObservation>& obs,
                           const PnpParams& params = {});

}  // namespace edge_slam
