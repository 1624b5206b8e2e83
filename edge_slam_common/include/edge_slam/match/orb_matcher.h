// Descriptor matching between a frame and map points / the last frame / a keyframe.
// Thresholds follow ORB-SLAM2: Hamming distance <= 100 (kThHigh) for projection searches,
// <= 50 (kThLow) for BoW searches, a best/second-best ratio test, and a rotation
// consistency histogram. Matches are written into frame.map_points; each search returns
// the number of new matches.
#pragma once
#include <memory>
#include <unordered_set>
#include <vector>

#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map_point.h"

namespace edge_slam {

// A map point predicted visible in a frame (see project_into_frame).
struct ProjectedPoint {
  std::shared_ptr<MapPoint> mp;
  float u = 0, v = 0;     // predicted undistorted pixel
  float u_right = -1;     // predicted virtual right coordinate (RGB-D)
  int level = 0;          // predicted pyramid level
  float view_cos = 1;     // cosine between viewing ray and the point's mean normal
};

// Frustum test: in front of the camera, inside the image bounds, within the point's
// scale-invariance distances and seen at most ~60 degrees off its mean normal
// (cos >= min_view_cos). Fills `out` and returns true when the point is predicted visible.
bool project_into_frame(const Frame& frame, const std::shared_ptr<MapPoint>& mp,
                        float min_view_cos, ProjectedPoint& out);

class OrbMatcher {
 public:
  static constexpr int kThLow = 50;
  static constexpr int kThHigh = 100;

  // nn_ratio: best distance must be below nn_ratio * second best.
  explicit OrbMatcher(float nn_ratio = 0.6f, bool check_orientation = true)
      : nn_ratio_(nn_ratio), check_orientation_(check_orientation) {}

  // Local map search: window th * (2.5 or 4 depending on view angle) * scale of the
  // predicted level; ratio test only when best and second best are on the same level.
  // Keypoints already holding an observed map point are skipped.
  int search_by_projection(Frame& frame, const std::vector<ProjectedPoint>& points, float th) const;

  // Motion model search: projects the last frame's inlier map points with frame's current
  // pose estimate; window th * scale of the last observation's level, levels restricted by
  // whether the camera moved forward or backward (RGB-D), rotation check.
  int search_by_projection(Frame& frame, const Frame& last, float th) const;

  // Relocalization guided search: projects keyframe points not in `already_found`
  // (map point ids) with the frame's pose; best distance must be <= max_distance.
  int search_by_projection(Frame& frame, const KeyFrame& kf,
                           const std::vector<std::shared_ptr<MapPoint>>& kf_points,
                           const std::unordered_set<uint32_t>& already_found, float th,
                           int max_distance) const;

  // BoW search: compares only features under the same vocabulary node (both BoW must be
  // computed); kf_points are the keyframe's map points per keypoint (null = none).
  int search_by_bow(const KeyFrame& kf, const std::vector<std::shared_ptr<MapPoint>>& kf_points,
                    Frame& frame) const;

 private:
  float nn_ratio_;
  bool check_orientation_;
};

}  // namespace edge_slam
