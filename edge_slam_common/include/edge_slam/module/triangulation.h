// New map points from unmatched keypoints of a new keyframe and its best covisible keyframes
// (ORB-SLAM2's CreateNewMapPoints, RGB-D flavour): BoW + epipolar matching, then a point is
// made by linear triangulation when the rays' parallax beats the depth sensor's, else from
// the keypoint depth of the keyframe seeing it with more parallax; it must lie in front of
// both cameras, reproject within chi2 5.991 (7.815 with the virtual right coordinate) and
// have distances to the cameras consistent with the two keypoints' pyramid levels.
#pragma once
#include <functional>
#include <memory>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

struct TriangulationParams {
  size_t num_covisibles = 10;  // ORB-SLAM2 RGB-D/stereo: 10
};

// Creates the points, links them to both keyframes and adds them to the map. `interrupt`
// (may be empty) is polled between neighbours: true stops early (a new keyframe is waiting).
// Both keyframes need their BoW; the caller holds Map::update_mutex().
std::vector<std::shared_ptr<MapPoint>> triangulate_new_points(Map& map, const std::shared_ptr<KeyFrame>& kf,
                                                              const TriangulationParams& params = {},
                                                              const std::function<bool()>& interrupt = {});

// One pair of keypoints -> a world point, or false when a check fails (exposed for tests).
bool triangulate_pair(const KeyFrame& kf1, size_t i1, const KeyFrame& kf2, size_t i2, Eigen::Vector3d& x_w);

}  // namespace edge_slam
