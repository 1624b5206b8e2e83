#pragma once
// Points the last frame's depth gives the next frame's motion-model search, beyond the map points
// it tracked (ORB-SLAM2's "visual odometry" points of UpdateLastFrame, which it makes in its
// localization mode: tracking with no mapper behind it). The split's mobile is such a tracker:
// its Local-Map holds only the KeyFrames the edge sent and its own, so in a fast turn the last
// frame may see few map points. On the synthetic look-away turn a frame that was not a KeyFrame
// left the next one 42 motion matches out of ~250 points, its pose landed 3.5-4.2 cm off a right
// prediction, and it became a KeyFrame (2026-12-05, docs/benchmarks/2026-12-05/lookaway_weak_keyframe).
// The points are temporary: observed by no KeyFrame (so replaceable by a map point in the
// local-map search, orb_matcher's already_matched, and absent from the local-map inlier count that
// decides whether the frame is tracked), placed from the last frame's pose, and dropped before the
// frame's KeyFrame decision. As in ORB-SLAM2's localization mode they count towards the motion
// model's own success (enough matches overall), so a last frame whose map points went bad (culled,
// replaced by an update) still gives the next frame a pose from which to search the Local-Map.
#include <cstdint>

#include "edge_slam/data/frame.h"

namespace edge_slam {

// The id every temporary point carries: outside any map's id range (util/ids.h), so a lookup by
// id never finds it and it never hides a map point's id.
inline constexpr uint32_t kDepthPointId = 0xfffffffeu;

bool is_depth_point(const MapPoint& mp);

// Gives `last` a temporary point at each keypoint with depth that tracks no map point, nearest
// first: all closer than `close_depth` and at least `min_points` (the tracked points count
// towards it), as ORB-SLAM2. `last` must have a pose. Returns how many were made.
int add_depth_points(Frame& last, float close_depth, int min_points);

// The frame's matches to temporary points that are not outliers of its pose.
int count_depth_points(const Frame& frame);

// Clears the frame's matches to temporary points (before its KeyFrame decision and before it
// becomes the next frame's last frame). Returns how many of them were inliers of its pose.
int drop_depth_points(Frame& frame);

}  // namespace edge_slam
