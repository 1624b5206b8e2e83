// Test helper: feature data with n identical keypoints and zero descriptors, for tests of map
// bookkeeping (covisibility, the KeyFrame database) where image content does not matter.
#pragma once
#include <memory>

#include "edge_slam/data/frame_features.h"
#include "edge_slam/sim/synthetic_camera.h"

namespace edge_slam {

inline std::shared_ptr<const FrameFeatures> blank_features(size_t n) {
  std::vector<cv::KeyPoint> keys(n, cv::KeyPoint(100.f, 100.f, 31.f));
  cv::Mat desc(static_cast<int>(n), 32, CV_8U, cv::Scalar(0));
  return FrameFeatures::build(synthetic_room_camera(30.0), std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f)),
                              keys, desc, cv::Mat());
}

}  // namespace edge_slam
