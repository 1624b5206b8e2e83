// Plain-data bundle adjustment problem shared by local and full (global) BA: keyframe poses,
// 3D points and the keypoint observations linking them. The map owner copies its keyframes
// and map points in, runs the adjustment, and writes the results (and outlier erasures) back.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "edge_slam/camera/pinhole_camera.h"

namespace edge_slam {

struct BaKeyFrame {
  uint32_t id = 0;
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();  // x_c = T_cw * x_w
  bool fixed = false;  // held constant (gauge / keyframes outside the local window)
};

struct BaPoint {
  uint32_t id = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world frame
  bool fixed = false;
};

struct BaObservation {
  uint32_t keyframe_id = 0;
  uint32_t point_id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // undistorted keypoint
  double right_x = -1.0;    // virtual right coordinate; < 0 => monocular term
  double inv_sigma2 = 1.0;  // 1 / sigma^2 of the keypoint's pyramid level
};

struct BundleAdjustmentProblem {
  PinholeCamera camera;
  std::vector<BaKeyFrame> keyframes;
  std::vector<BaPoint> points;
  std::vector<BaObservation> observations;
};

struct BundleAdjustmentResult {
  bool ok = false;
  bool aborted = false;  // the abort flag stopped the solver early; results are still usable if ok
  std::string message;
  // Same order and ids as the problem's vectors, with the adjusted values (inputs on failure).
  std::vector<BaKeyFrame> keyframes;
  std::vector<BaPoint> points;
  // Indices into problem.observations whose final chi2 exceeds 5.991 (mono) / 7.815 (stereo),
  // whose point ends at or behind the camera, or whose data is unusable (non-finite values,
  // non-finite point). Observations naming an unknown keyframe or point are ignored, not listed.
  std::vector<size_t> outlier_observations;
  // Sum of chi2 (no robust kernel) over the observations not reported as outliers, before and
  // after the adjustment, so the two figures compare the same set.
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;  // Levenberg-Marquardt iterations over all passes
};

}  // namespace edge_slam
