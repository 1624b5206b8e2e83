// Glue between a Frame's matches and the pose-only optimiser.
#pragma once
#include "edge_slam/data/frame.h"

namespace edge_slam {

// Optimises frame's pose against its matched map points (keeps the current pose as the
// initial guess), writes the outlier flags and returns the number of inliers
// (-1 if the optimiser refused, e.g. too few matches; pose untouched then).
int optimize_frame_pose(Frame& frame);

// Removes matches flagged as outliers; returns how many inlier matches remain.
int discard_outliers(Frame& frame);

}  // namespace edge_slam
