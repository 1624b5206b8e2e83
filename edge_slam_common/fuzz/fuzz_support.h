// What every fuzz target shares: the receiver's configuration (the camera the seed messages
// were made for, the ORB pyramid, message limits) and a small vocabulary trained in code.
#pragma once
#include <edge_slam/camera/pinhole_camera.h>
#include <edge_slam/data/bow_vocabulary.h>
#include <edge_slam/data/scale_pyramid.h>
#include <edge_slam/io/vocabulary_io.h>
#include <edge_slam_bridge/message_conversion.h>

#include <memory>
#include <random>
#include <stdexcept>

#include "../bridge/test/support/wire_fixtures.h"

namespace edge_slam {
namespace fuzz {

inline const PinholeCamera& camera() {
  static const PinholeCamera c = fixtures::pinhole_camera();
  return c;
}

inline std::shared_ptr<const ScalePyramid> pyramid() {
  static const auto p = std::make_shared<const ScalePyramid>(ScalePyramid::make(8, 1.2f));
  return p;
}

// Smaller than the defaults so one input cannot take seconds (the checks are the same code).
inline const MessageLimits& limits() {
  static const MessageLimits l = [] {
    MessageLimits m;
    m.max_keypoints = 2000;
    m.max_new_points = 2000;
    m.max_keyframes_per_update = 50;
    m.max_points_per_update = 20000;
    m.max_message_bytes = 4u << 20;
    return m;
  }();
  return l;
}

inline cv::Mat random_descriptors(int rows, unsigned seed) {
  std::mt19937 rng(seed);
  cv::Mat d(rows, 32, CV_8U);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 32; ++c) d.at<uint8_t>(r, c) = static_cast<uint8_t>(rng());
  return d;
}

// Loads a vocabulary file image (either format) and uses the tree once, as tracking would;
// refusing the bytes with std::runtime_error is a correct outcome.
inline void load_and_use_vocabulary(const uint8_t* data, size_t size) {
  try {
    const BowVocabulary voc = load_vocabulary_from_bytes(data, size, "fuzz input");
    static const cv::Mat descriptors = random_descriptors(20, 5);
    BowVector bow;
    FeatureVector features;
    voc.transform(descriptors, bow, features, 1);
  } catch (const std::runtime_error&) {
  }
}

inline std::shared_ptr<const BowVocabulary> vocabulary() {
  static const auto v = [] {
    auto voc = std::make_shared<BowVocabulary>();
    VocabularyParams params;
    params.branching = 3;
    params.levels = 2;
    voc->train({random_descriptors(60, 1), random_descriptors(60, 2)}, params);
    return std::shared_ptr<const BowVocabulary>(voc);
  }();
  return v;
}

}  // namespace fuzz
}  // namespace edge_slam
