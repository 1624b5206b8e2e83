// Glue between a Frame's matches and the pose-only optimiser.
#pragma once
#include "edge_slam/data/frame.h"
#include "edge_slam/optimize/pose_optimizer.h"

namespace edge_slam {

// The pose-optimiser observation of `point_world` at keypoint i of `f`: its undistorted pixel,
// its virtual right coordinate (stereo-projected term when the keypoint has a depth) and the
// inverse variance of its pyramid level.
PoseObservation pose_observation(const FrameFeatures& f, size_t i, const Eigen::Vector3d& point_world);

// Optimises frame's pose against its matched map points (keeps the current pose as the
// initial guess), writes the outlier flags and returns the number of inliers
// (-1 if the optimiser refused, e.g. too few matches; pose untouched then).
int optimize_frame_pose(Frame& frame);

// Removes matches flagged as outliers; returns how many inlier matches remain.
int discard_outliers(Frame& frame);

}  // namespace edge_slam
