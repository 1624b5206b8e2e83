// Feature source for vocabulary training: the SLAM ORB extractor with its default (ORB-SLAM2)
// parameters, so the vocabulary's words partition exactly the descriptors tracking produces.
#include "edge_slam/data/bow_training_features.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "edge_slam/feature/orb_extractor.h"

namespace edge_slam {

cv::Mat extract_training_descriptors(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("extract_training_descriptors: expected a non-empty 8-bit gray image, got type " +
                                std::to_string(gray.type()) + " (" + std::to_string(gray.cols) + " x " +
                                std::to_string(gray.rows) + ")");
  static const OrbExtractor extractor{OrbParams()};  // extract() is const and thread-safe
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.extract(gray, keypoints, descriptors);
  return descriptors;
}

}  // namespace edge_slam
