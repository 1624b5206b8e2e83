// The vocabulary on real ORB features of procedurally drawn scenes: overlapping views of one
// scene must score clearly higher than views of different scenes, and the training feature
// source must reject what the extractor cannot take.
#include <gtest/gtest.h>

#include <vector>

#include "edge_slam/data/bow_training_features.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

namespace {

// Each scene is a large texture; a view is a 320x240 window into it.
cv::Mat view(const cv::Mat& scene, int x, int y) { return scene(cv::Rect(x, y, 320, 240)).clone(); }

class BowOrbFeaturesTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    for (uint64_t seed = 1; seed <= 6; ++seed) scenes_.push_back(make_synthetic_texture(cv::Size(480, 360), seed));
    std::vector<cv::Mat> training;
    for (const cv::Mat& scene : scenes_)
      for (int x : {0, 80, 160})
        for (int y : {0, 120}) training.push_back(extract_training_descriptors(view(scene, x, y)));
    VocabularyParams params;
    params.branching = 10;
    params.levels = 4;
    vocabulary_.train(training, params);
  }
  static std::vector<cv::Mat> scenes_;
  static BowVocabulary vocabulary_;

  BowVector bow_of(const cv::Mat& image) const {
    BowVector bow;
    vocabulary_.transform(extract_training_descriptors(image), bow);
    return bow;
  }
};

std::vector<cv::Mat> BowOrbFeaturesTest::scenes_;
BowVocabulary BowOrbFeaturesTest::vocabulary_;

}  // namespace

TEST_F(BowOrbFeaturesTest, OverlappingViewsOfOneSceneScoreHigherThanOtherScenes) {
  ASSERT_GT(vocabulary_.size(), 100u);
  for (size_t s = 0; s < scenes_.size(); ++s) {
    // Offsets between the training grid positions: the exact views were not trained on.
    const BowVector a = bow_of(view(scenes_[s], 40, 60));
    const BowVector b = bow_of(view(scenes_[s], 70, 80));
    const double same = BowVocabulary::score(a, b);
    for (size_t other = 0; other < scenes_.size(); ++other) {
      if (other == s) continue;
      const double different = BowVocabulary::score(a, bow_of(view(scenes_[other], 40, 60)));
      EXPECT_GT(same, 2 * different) << "scene " << s << " vs " << other << ": same " << same
                                     << ", different " << different;
    }
  }
}

TEST_F(BowOrbFeaturesTest, SelfScoreIsOne) {
  const BowVector a = bow_of(view(scenes_[2], 10, 20));
  EXPECT_NEAR(BowVocabulary::score(a, a), 1.0, 1e-12);
}

TEST(BowTrainingFeatures, ExtractsOrbDescriptorsAndRejectsColourImages) {
  const cv::Mat gray = make_synthetic_texture(cv::Size(320, 240), 9);
  const cv::Mat d = extract_training_descriptors(gray);
  EXPECT_GT(d.rows, 200);
  EXPECT_EQ(d.cols, 32);
  EXPECT_EQ(d.type(), CV_8UC1);
  cv::Mat colour;
  cv::merge(std::vector<cv::Mat>{gray, gray, gray}, colour);
  EXPECT_THROW(extract_training_descriptors(colour), std::invalid_argument);
  EXPECT_THROW(extract_training_descriptors(cv::Mat()), std::invalid_argument);
}
