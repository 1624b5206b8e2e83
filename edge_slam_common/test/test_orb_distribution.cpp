// The extractor returns about num_features keypoints, spread evenly over the image.
#include <gtest/gtest.h>

#include <cmath>

#include "edge_slam/feature/orb_extractor.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

TEST(OrbDistribution, CountNearTargetAndNoCrowdedCell) {
  const cv::Mat image = make_synthetic_texture(cv::Size(640, 480), 7);
  const OrbExtractor extractor;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.extract(image, keypoints, descriptors);

  const int total = static_cast<int>(keypoints.size());
  EXPECT_NEAR(total, 1000, 100);
  ASSERT_EQ(descriptors.rows, total);

  constexpr int kGrid = 4;
  int cells[kGrid][kGrid] = {};
  for (const cv::KeyPoint& kp : keypoints) {
    const int c = std::min(kGrid - 1, static_cast<int>(kp.pt.x * kGrid / image.cols));
    const int r = std::min(kGrid - 1, static_cast<int>(kp.pt.y * kGrid / image.rows));
    ++cells[r][c];
  }
  const double share = static_cast<double>(total) / (kGrid * kGrid);
  int fullest = 0, emptiest = total;
  for (auto& row : cells)
    for (int count : row) {
      EXPECT_LE(count, 3.0 * share);
      fullest = std::max(fullest, count);
      emptiest = std::min(emptiest, count);
    }
  std::printf("keypoints %d, per 4x4 cell: min %d max %d (share %.1f)\n", total, emptiest, fullest, share);
}

TEST(OrbDistribution, EveryLevelContributesItsBudget) {
  const cv::Mat image = make_synthetic_texture(cv::Size(640, 480), 8);
  const OrbExtractor extractor;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.extract(image, keypoints, descriptors);

  std::vector<int> per_level(extractor.num_levels(), 0);
  for (const cv::KeyPoint& kp : keypoints) {
    ASSERT_GE(kp.octave, 0);
    ASSERT_LT(kp.octave, extractor.num_levels());
    ++per_level[kp.octave];
  }
  for (int level = 0; level < extractor.num_levels(); ++level) {
    EXPECT_LE(per_level[level], extractor.features_per_level()[level]) << "level " << level;
    EXPECT_GE(per_level[level], 0.8 * extractor.features_per_level()[level]) << "level " << level;
  }
}
