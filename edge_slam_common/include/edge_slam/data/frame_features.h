// Immutable per-image feature data: keypoints (raw and undistorted), per-keypoint depth and
// virtual right coordinate, ORB descriptors and the search grid. A Frame and the KeyFrame
// made from it share one instance, so promoting a frame to a keyframe copies nothing.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "edge_slam/camera/pinhole_camera.h"
#include "edge_slam/data/feature_grid.h"
#include "edge_slam/data/scale_pyramid.h"
#include "edge_slam/util/instance_count.h"

namespace edge_slam {

struct FrameFeatures {
  PinholeCamera camera;
  std::shared_ptr<const ScalePyramid> pyramid;
  std::vector<cv::KeyPoint> keys;     // raw pixel coordinates (as extracted)
  std::vector<cv::KeyPoint> keys_un;  // undistorted pixel coordinates
  std::vector<float> depth;           // metres; <= 0 means no valid depth
  std::vector<float> right_x;         // virtual right-image u = u - bf / z; < 0 means none
  cv::Mat descriptors;                // N x 32, CV_8U
  ImageBounds bounds;                 // undistorted image borders
  FeatureGrid grid;

  size_t size() const { return keys.size(); }
  bool has_depth(size_t i) const { return depth[i] > 0; }
  bool is_close(size_t i) const { return depth[i] > 0 && depth[i] < camera.th_depth; }
  const uint8_t* descriptor(size_t i) const { return descriptors.ptr<uint8_t>(static_cast<int>(i)); }
  // Point in the camera frame from the undistorted keypoint and its depth (depth must be valid).
  Eigen::Vector3d unproject_camera(size_t i) const {
    return camera.unproject(keys_un[i].pt.x, keys_un[i].pt.y, depth[i]);
  }

  // Undistorts keypoints, samples depth at the raw keypoint pixels and builds the grid.
  // `depth_image` is CV_16UC1 (scaled by camera.depth_factor) or CV_32FC1 metres, or empty
  // (no depth at all). Zero, negative and NaN depths count as missing.
  static std::shared_ptr<const FrameFeatures> build(const PinholeCamera& camera,
                                                    std::shared_ptr<const ScalePyramid> pyramid,
                                                    std::vector<cv::KeyPoint> keys,
                                                    cv::Mat descriptors, const cv::Mat& depth_image);
  InstanceCount<FrameFeatures> instance_count_;  // util/instance_count.h: both nodes' memory rows report it
};

// Undistorted image borders for a camera (the full image when there is no distortion).
ImageBounds compute_image_bounds(const PinholeCamera& camera);

}  // namespace edge_slam
