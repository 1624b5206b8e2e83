// Rolling-shutter compensation of a frame's keypoints.
// A rolling-shutter sensor exposes row y at t_mid + (y / height - 1/2) * readout, so during a
// fast turn the image is sheared by several pixels (fr1's Kinect at 100 deg/s: ~30 px from top
// to bottom). With the camera's velocity over the frame, each keypoint and its depth are moved
// to where a global-shutter camera at the frame's time stamp would have seen them.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>

#include "edge_slam/data/frame_features.h"

namespace edge_slam {

// Constant body velocity of the camera, in the camera frame: over a short time tau the camera
// moves by T_{t <- t+tau} ~ (rotation angular * tau, translation linear * tau).
struct CameraVelocity {
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // rad/s
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // m/s

  // From the motion between two frames dt seconds apart: T_later_earlier maps points of the
  // earlier camera frame into the later one (the tracker's velocity model).
  static CameraVelocity from_motion(const Eigen::Isometry3d& T_later_earlier, double dt);
};

// A copy of `in` with keys_un, depth, right_x and the grid moved to the time stamp's camera.
// Raw keypoints, descriptors and the keypoint order are kept (matches stay valid). Keypoints
// without depth are only rotated. Returns `in` itself when the readout is zero or the velocity
// is not finite or implausible (over 720 deg/s or 10 m/s).
std::shared_ptr<const FrameFeatures> compensate_rolling_shutter(
    const std::shared_ptr<const FrameFeatures>& in, const CameraVelocity& velocity);

}  // namespace edge_slam
