#pragma once
// Where a KeyFrame's new point is when it was made from its source keypoint's depth, as the
// mobile's tracking makes them (ORB-SLAM2's RGB-D KeyFrame creation): the keypoint back-projected
// with the KeyFrame's pose. A KeyFrame record already carries that keypoint and its depth, so on
// the wire the positions are redundant (12 of the 18 bytes a new point costs; on fr1_rpy about a
// tenth of a KeyFrame message). The sender leaves them out when the receiver's back-projection of
// the quantised keypoints gives them back closely enough, and the receiver computes them again
// (KeyFrame.msg, format 4; edge_slam_bridge keyframe_conversion.cpp).
#include <cstddef>
#include <optional>

#include <Eigen/Geometry>

#include "edge_slam/io/wire_records.h"

namespace edge_slam {

// How far a position left out may be from the one the receiver computes: within a Kinect-class
// depth sensor's noise at 1 m (a few mm) and far below it at the ranges points are made from;
// above what the 1/8-pixel and 1/4-mm quantisation moves a point there (1/16 px at 4 m: 0.5 mm).
constexpr double kNewPointPositionTolerance = 0.002;  // metres

// The undistorted pixel (x, y) at depth z (metres) in the world of the camera pose T_wc;
// nullopt when z is not a valid depth or the intrinsics are degenerate.
std::optional<Eigen::Vector3d> back_project(const CameraRecord& camera, const Eigen::Isometry3d& T_wc, double x,
                                            double y, double z);

// The keypoint `kp_index` of `r` back-projected with its depth and r.T_wc; nullopt when the
// index is out of range or the keypoint has no valid depth.
std::optional<Eigen::Vector3d> back_projected_keypoint(const KeyFrameRecord& r, size_t kp_index);

}  // namespace edge_slam
