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
#include "edge_slam/io/config_file.h"

namespace edge_slam {

struct LoopVerifierParams {
  int min_bow_matches = 20;
  int min_ransac_inliers = 20;
  int min_refined_inliers = 20;
  int min_total_matches = 40;
  // Reprojection refinement with each keypoint's depth (stereo-projected terms, the RGB-D pose
  // optimisation's), loop_closing/verify_with_depth; false = ORB-SLAM2's (u, v) terms only
  // (optimize/relative_pose_optimizer.h says why that is ambiguous).
  bool refine_with_depth = true;
  // The accepted transform refined once more on all the current keyframe's matches with the
  // loop group (loop_closing/refine_on_loop_group, as ORB-SLAM3 refines a place match on its
  // covisible window); false = ORB-SLAM2's (the refinement on the two keyframes' shared points
  // stands).
  bool refine_on_loop_group = true;
};

// loop_closing/verify_with_depth and refine_on_loop_group of config/slam.yaml (the monolithic
// runner and the edge).
LoopVerifierParams load_loop_verifier_params(const ConfigMap& cfg);

struct LoopMatch {
  std::shared_ptr<KeyFrame> loop_kf;
  Eigen::Isometry3d T_cw_corrected = Eigen::Isometry3d::Identity();  // current keyframe in the loop's frame
  Eigen::Isometry3d T_cw_aligned = Eigen::Isometry3d::Identity();    // ... from the 3-D RANSAC alone (diagnostics)
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
