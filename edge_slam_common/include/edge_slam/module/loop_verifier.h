// Geometric verification of loop candidates (ORB-SLAM2's ComputeSim3 with the scale fixed,
// RGB-D): BoW map point matches (>= 20), RANSAC SE(3) alignment of the matched points in the
// two camera frames (>= 20 inliers), guided search with that transform, reprojection
// refinement (optimize_relative_pose, >= 20 inliers), then the candidate's covisible group's
// points projected with the corrected pose; accepted with >= 40 matches in total.
#pragma once
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

struct LoopVerifierParams {
  int min_bow_matches = 20;
  int min_ransac_inliers = 20;
  int min_refined_inliers = 20;
  int min_total_matches = 40;
};

struct LoopMatch {
  std::shared_ptr<KeyFrame> loop_kf;
  Eigen::Isometry3d T_cw_corrected = Eigen::Isometry3d::Identity();  // current keyframe in the loop's frame
  std::vector<std::shared_ptr<MapPoint>> matched;      // per current keypoint: loop-side point
  std::vector<std::shared_ptr<MapPoint>> loop_points;  // points of the loop keyframe's group
  int num_matches = 0;
};

// Tries the candidates in order; true with `out` filled for the first that passes. `log`
// receives one line per rejected candidate (why), for diagnostics.
bool verify_loop(const Map& map, const std::shared_ptr<KeyFrame>& kf,
                 const std::vector<std::shared_ptr<KeyFrame>>& candidates, LoopMatch& out,
                 std::string* log = nullptr, const LoopVerifierParams& params = {});

}  // namespace edge_slam
