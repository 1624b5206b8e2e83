// Keyframe-to-keyframe and points-to-keyframe matching used by local mapping and loop
// closing (ORB-SLAM2's SearchForTriangulation, SearchByBoW(KF, KF), SearchByProjection with
// a loop pose, and Fuse). Thresholds as in OrbMatcher: Hamming <= kThLow (50) everywhere
// here, ratio tests where stated, rotation-consistency histograms for the two BoW searches.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <utility>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/map_point.h"

namespace edge_slam {

// Fundamental matrix F12 with x1^T F12 x2 = 0 for undistorted pixels of kf1 and kf2.
Eigen::Matrix3d fundamental_matrix(const KeyFrame& kf1, const KeyFrame& kf2);

// Pairs (keypoint in kf1, keypoint in kf2) of keypoints that have no map point yet, share a
// BoW node, match by descriptor and satisfy the epipolar constraint (distance to the line
// below 3.84 sigma^2 of kf2's level); keypoints close to the epipole are skipped when
// neither has depth. Both keyframes must have their BoW.
std::vector<std::pair<size_t, size_t>> search_for_triangulation(const KeyFrame& kf1, const KeyFrame& kf2,
                                                                const Map& map,
                                                                const Eigen::Matrix3d& F12);

// Map point matches between two keyframes (both keypoints holding a point) by BoW:
// matches12[i] = kf2's point matched to kf1's keypoint i (null otherwise). Returns the count.
int search_by_bow(const KeyFrame& kf1, const KeyFrame& kf2, const Map& map,
                  std::vector<std::shared_ptr<MapPoint>>& matches12, float nn_ratio = 0.75f);

// Projects `points` with the pose T_cw into kf and matches them to keypoints whose slot in
// `matched` (one per keypoint of kf) is still empty; points already in `matched` are skipped.
// Returns the number of new matches.
int search_by_projection(const KeyFrame& kf, const Eigen::Isometry3d& T_cw,
                         const std::vector<std::shared_ptr<MapPoint>>& points,
                         std::vector<std::shared_ptr<MapPoint>>& matched, float th);

struct FuseOptions {
  float th = 3.f;               // window radius factor (x scale of the predicted level)
  bool projected_wins = false;  // loop fusion: the projected point replaces the keyframe's one
  bool check_reprojection = true;  // reject candidates beyond chi2 5.991 / 7.815
};

// Projects `points` into kf (pose T_cw) and fuses each with its best matching keypoint: a
// keypoint without a (good) point gets an observation, one with a point has the two merged
// (the point with more observations survives unless projected_wins). Returns the number of
// fused or added points. The caller holds Map::update_mutex().
int fuse(Map& map, const std::shared_ptr<KeyFrame>& kf, const Eigen::Isometry3d& T_cw,
         const std::vector<std::shared_ptr<MapPoint>>& points, const FuseOptions& options);

// fuse() in two halves, so the search can run without the map's update mutex: the loop
// correction finds its matches while other robots map, then applies them under the mutex.
// find_fusion_matches reads kf and the points only (their own mutexes); apply_fusion_matches
// applies each pair as fuse() would, to the map as it is then (a point gone bad or already in
// kf meanwhile is skipped; the keypoint's point is read again). The caller of apply holds
// Map::update_mutex().
struct FusionMatches {
  std::shared_ptr<KeyFrame> kf;
  std::vector<std::pair<std::shared_ptr<MapPoint>, size_t>> pairs;  // point, keypoint index in kf
};
FusionMatches find_fusion_matches(const std::shared_ptr<KeyFrame>& kf, const Eigen::Isometry3d& T_cw,
                                  const std::vector<std::shared_ptr<MapPoint>>& points, const FuseOptions& options);
int apply_fusion_matches(Map& map, const FusionMatches& matches, const FuseOptions& options);

}  // namespace edge_slam
