// Feature source for vocabulary training.
// TODO(orb): switch to edge_slam::OrbExtractor (same parameters) once it is merged, so training
// and SLAM share one extractor; until then OpenCV's ORB with ORB-SLAM2's pyramid settings.
#include "edge_slam/data/bow_training_features.h"

#include <opencv2/features2d.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace edge_slam {

cv::Mat extract_training_descriptors(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("extract_training_descriptors: expected a non-empty 8-bit gray image, got type " +
                                std::to_string(gray.type()) + " (" + std::to_string(gray.cols) + " x " +
                                std::to_string(gray.rows) + ")");
  // 1000 features, scale 1.2, 8 levels: ORB-SLAM2's TUM RGB-D settings.
  thread_local cv::Ptr<cv::ORB> orb = cv::ORB::create(1000, 1.2f, 8);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  return descriptors;
}

}  // namespace edge_slam
