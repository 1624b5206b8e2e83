// Every keypoint field follows the documented conventions.
#include <gtest/gtest.h>

#include "edge_slam/feature/orb_extractor.h"
#include "edge_slam/feature/orb_patch.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

TEST(OrbKeypointFields, ConventionsHold) {
  const cv::Mat image = make_synthetic_texture(cv::Size(640, 480), 3);
  const OrbExtractor extractor;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.extract(image, keypoints, descriptors);
  ASSERT_FALSE(keypoints.empty());
  EXPECT_EQ(descriptors.type(), CV_8UC1);
  EXPECT_EQ(descriptors.cols, 32);
  EXPECT_EQ(descriptors.rows, static_cast<int>(keypoints.size()));

  int previous_octave = 0;
  float previous_y = -1.0f;
  for (const cv::KeyPoint& kp : keypoints) {
    EXPECT_GE(kp.octave, previous_octave) << "keypoints are grouped by level, finest first";
    // Within a level in row order: the wire codes y as steps (io/keypoint_coding.h).
    if (kp.octave == previous_octave) EXPECT_GE(kp.pt.y, previous_y);
    previous_octave = kp.octave;
    previous_y = kp.pt.y;
    const float scale = extractor.scale_factors()[kp.octave];
    EXPECT_FLOAT_EQ(kp.size, kOrbPatchSize * scale);
    EXPECT_GE(kp.angle, 0.0f);
    EXPECT_LT(kp.angle, 360.0f);
    EXPECT_GT(kp.response, 0.0f);
    // The patch at the keypoint's level lies inside the image.
    const float margin = kOrbPatchRadius * scale;
    EXPECT_GE(kp.pt.x, margin);
    EXPECT_GE(kp.pt.y, margin);
    EXPECT_LE(kp.pt.x, image.cols - 1 - margin);
    EXPECT_LE(kp.pt.y, image.rows - 1 - margin);
  }
}

TEST(OrbKeypointFields, ScaleTables) {
  const OrbExtractor extractor;
  ASSERT_EQ(extractor.num_levels(), 8);
  ASSERT_EQ(extractor.scale_factors().size(), 8u);
  EXPECT_FLOAT_EQ(extractor.scale_factor(), 1.2f);
  int budget = 0;
  for (int level = 0; level < 8; ++level) {
    const float s = std::pow(1.2f, static_cast<float>(level));
    EXPECT_NEAR(extractor.scale_factors()[level], s, 1e-4f * s);
    EXPECT_NEAR(extractor.inv_scale_factors()[level], 1.0f / s, 1e-5f);
    EXPECT_NEAR(extractor.level_sigma2()[level], s * s, 1e-4f * s * s);
    EXPECT_NEAR(extractor.inv_level_sigma2()[level], 1.0f / (s * s), 1e-5f);
    if (level > 0) {
      EXPECT_LE(extractor.features_per_level()[level], extractor.features_per_level()[level - 1] + 1);
    }
    budget += extractor.features_per_level()[level];
  }
  EXPECT_EQ(budget, 1000);
  EXPECT_NEAR(extractor.features_per_level()[0], 1000 * (1 - 1 / 1.2) / (1 - std::pow(1 / 1.2, 8)), 1.0);
}
