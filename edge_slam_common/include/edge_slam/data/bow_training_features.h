// The features a vocabulary is trained on. They must be the features SLAM extracts at run time,
// otherwise the words do not match what tracking and loop detection look up; every trainer
// (folder/TUM tool, bag tool) goes through this one function.
#pragma once
#include <opencv2/core.hpp>

namespace edge_slam {

// gray: 8-bit single-channel image. Returns N x 32 CV_8U ORB descriptors (possibly empty).
// Throws std::invalid_argument for other image types.
cv::Mat extract_training_descriptors(const cv::Mat& gray);

}  // namespace edge_slam
