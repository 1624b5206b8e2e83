// Training, transform and scoring of the vocabulary on synthetic clustered descriptors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/feature/descriptor_distance.h"

using namespace edge_slam;

namespace {

// A "world" of appearance prototypes; an image shows a random subset of them with bit noise.
cv::Mat random_prototypes(int count, std::mt19937& rng) {
  cv::Mat m(count, kDescriptorBytes, CV_8U);
  for (int r = 0; r < count; ++r)
    for (int c = 0; c < kDescriptorBytes; ++c) m.at<uint8_t>(r, c) = static_cast<uint8_t>(rng());
  return m;
}

cv::Mat noisy_image(const cv::Mat& prototypes, int features, int max_flips, std::mt19937& rng) {
  cv::Mat m(features, kDescriptorBytes, CV_8U);
  for (int r = 0; r < features; ++r) {
    prototypes.row(static_cast<int>(rng() % prototypes.rows)).copyTo(m.row(r));
    const int flips = static_cast<int>(rng() % (max_flips + 1));
    for (int f = 0; f < flips; ++f) {
      const int bit = static_cast<int>(rng() % 256);
      m.at<uint8_t>(r, bit / 8) ^= static_cast<uint8_t>(1u << (bit % 8));
    }
  }
  return m;
}

class BowVocabularyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(42);
    prototypes_ = random_prototypes(300, rng);
    for (int i = 0; i < 40; ++i) training_.push_back(noisy_image(prototypes_, 150, 6, rng));
    VocabularyParams params;
    params.branching = 6;
    params.levels = 3;
    vocabulary_.train(training_, params);
  }
  cv::Mat prototypes_;
  std::vector<cv::Mat> training_;
  BowVocabulary vocabulary_;
};

double l1_norm(const BowVector& v) {
  double s = 0;
  for (const auto& e : v) s += std::abs(e.second);
  return s;
}

}  // namespace

TEST_F(BowVocabularyTest, TreeShape) {
  EXPECT_FALSE(vocabulary_.empty());
  EXPECT_EQ(vocabulary_.branching(), 6);
  EXPECT_EQ(vocabulary_.levels(), 3);
  EXPECT_GT(vocabulary_.size(), 100u);
  EXPECT_LE(vocabulary_.size(), 216u);  // at most k^L words
  for (WordId w = 0; w < vocabulary_.size(); ++w) {
    EXPECT_TRUE(std::isfinite(vocabulary_.idf(w)));
    EXPECT_GE(vocabulary_.idf(w), 0.0);
  }
}

TEST_F(BowVocabularyTest, BowVectorIsL1NormalisedAndConsistentWithWordOf) {
  BowVector bow;
  FeatureVector features;
  vocabulary_.transform(training_[0], bow, features, 1);
  ASSERT_FALSE(bow.empty());
  EXPECT_NEAR(l1_norm(bow), 1.0, 1e-12);
  std::set<WordId> words;
  for (int r = 0; r < training_[0].rows; ++r) {
    const WordId w = vocabulary_.word_of(training_[0].ptr<uint8_t>(r));
    ASSERT_LT(w, vocabulary_.size());
    if (vocabulary_.idf(w) > 0) words.insert(w);
  }
  std::set<WordId> bow_words;
  for (const auto& e : bow) bow_words.insert(e.first);
  EXPECT_EQ(words, bow_words);

  // The direct index lists every kept feature exactly once, in increasing order per node.
  std::set<uint32_t> listed;
  for (const auto& node : features) {
    EXPECT_TRUE(std::is_sorted(node.second.begin(), node.second.end()));
    for (uint32_t i : node.second) EXPECT_TRUE(listed.insert(i).second);
  }
  size_t kept = 0;
  for (int r = 0; r < training_[0].rows; ++r)
    kept += vocabulary_.idf(vocabulary_.word_of(training_[0].ptr<uint8_t>(r))) > 0;
  EXPECT_EQ(listed.size(), kept);
}

TEST_F(BowVocabularyTest, DirectIndexLevels) {
  BowVector bow;
  FeatureVector at_words, at_root, one_up;
  vocabulary_.transform(training_[1], bow, at_words, 0);
  vocabulary_.transform(training_[1], bow, at_root, vocabulary_.levels());
  vocabulary_.transform(training_[1], bow, one_up, 1);
  ASSERT_EQ(at_root.size(), 1u);
  EXPECT_EQ(at_root.begin()->first, 0u);
  // Grouping at a higher level merges groups.
  EXPECT_LE(one_up.size(), at_words.size());
  EXPECT_GE(one_up.size(), 2u);
  // levels_up = 0 groups by word node.
  for (const auto& node : at_words)
    for (uint32_t i : node.second) {
      const WordId w = vocabulary_.word_of(training_[1].ptr<uint8_t>(static_cast<int>(i)));
      EXPECT_EQ(vocabulary_.node_of_word(w), node.first);
    }
}

TEST_F(BowVocabularyTest, ScoreProperties) {
  std::mt19937 rng(99);
  const cv::Mat unrelated_prototypes = random_prototypes(300, rng);
  const cv::Mat same_world = noisy_image(prototypes_, 150, 6, rng);
  const cv::Mat other_world = noisy_image(unrelated_prototypes, 150, 6, rng);
  BowVector a, b, c;
  vocabulary_.transform(training_[3], a);
  vocabulary_.transform(same_world, b);
  vocabulary_.transform(other_world, c);

  EXPECT_NEAR(BowVocabulary::score(a, a), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(BowVocabulary::score(a, b), BowVocabulary::score(b, a));
  EXPECT_DOUBLE_EQ(BowVocabulary::score(a, c), BowVocabulary::score(c, a));
  for (double s : {BowVocabulary::score(a, b), BowVocabulary::score(a, c), BowVocabulary::score(b, c)}) {
    EXPECT_GE(s, 0.0);
    EXPECT_LE(s, 1.0);
  }
  EXPECT_LT(BowVocabulary::score(a, c), 0.3);
  EXPECT_EQ(BowVocabulary::score(a, BowVector()), 0.0);

  // Scaling does not matter: the score normalises.
  BowVector scaled = a;
  for (auto& e : scaled) e.second *= 7.5;
  EXPECT_NEAR(BowVocabulary::score(a, scaled), 1.0, 1e-12);
}

TEST_F(BowVocabularyTest, OverlappingImagesScoreHigherThanDisjointOnes) {
  // Two views sharing most features vs. a view of disjoint prototypes.
  std::mt19937 rng(5);
  const cv::Mat first = prototypes_.rowRange(0, 100).clone();
  cv::Mat overlapping;
  cv::vconcat(prototypes_.rowRange(10, 100), prototypes_.rowRange(200, 210), overlapping);
  const cv::Mat disjoint = prototypes_.rowRange(100, 200).clone();
  BowVector a, b, c;
  vocabulary_.transform(first, a);
  vocabulary_.transform(overlapping, b);
  vocabulary_.transform(disjoint, c);
  EXPECT_GT(BowVocabulary::score(a, b), 0.6);
  EXPECT_GT(BowVocabulary::score(a, b), BowVocabulary::score(a, c) + 0.3);
}

TEST_F(BowVocabularyTest, TrainingIsDeterministicForASeed) {
  VocabularyParams params;
  params.branching = 6;
  params.levels = 3;
  BowVocabulary again;
  again.train(training_, params);
  ASSERT_EQ(again.size(), vocabulary_.size());
  const BowTreeArrays x = vocabulary_.to_arrays(), y = again.to_arrays();
  EXPECT_EQ(x.parents, y.parents);
  EXPECT_EQ(x.descriptors, y.descriptors);
  EXPECT_EQ(x.weights, y.weights);
}

TEST_F(BowVocabularyTest, RejectsWrongDescriptorTypes) {
  BowVector bow;
  EXPECT_THROW(vocabulary_.transform(cv::Mat(10, 32, CV_32F, cv::Scalar(0)), bow), std::invalid_argument);
  EXPECT_THROW(vocabulary_.transform(cv::Mat(10, 64, CV_8U, cv::Scalar(0)), bow), std::invalid_argument);
  vocabulary_.transform(cv::Mat(), bow);  // no features: empty vector, no error
  EXPECT_TRUE(bow.empty());
}

TEST(BowVocabularyTraining, RejectsBadInput) {
  BowVocabulary v;
  VocabularyParams params;
  EXPECT_THROW(v.train({}, params), std::invalid_argument);
  EXPECT_THROW(v.train({cv::Mat()}, params), std::invalid_argument);
  EXPECT_THROW(v.train({cv::Mat(5, 32, CV_32F, cv::Scalar(0))}, params), std::invalid_argument);
  params.branching = 1;
  EXPECT_THROW(v.train({cv::Mat(5, 32, CV_8U, cv::Scalar(0))}, params), std::invalid_argument);
  BowVector bow;
  EXPECT_THROW(v.transform(cv::Mat(1, 32, CV_8U, cv::Scalar(0)), bow), std::logic_error);
}

TEST(BowVocabularyTraining, DegenerateInputsStillGiveAValidTree) {
  BowVocabulary v;
  VocabularyParams params;
  params.branching = 4;
  params.levels = 3;
  // All descriptors identical: a single word, no chain of single-child nodes.
  v.train({cv::Mat(20, 32, CV_8U, cv::Scalar(7)), cv::Mat(5, 32, CV_8U, cv::Scalar(7))}, params);
  EXPECT_EQ(v.size(), 1u);
  EXPECT_EQ(v.node_count(), 2u);
  EXPECT_DOUBLE_EQ(v.idf(0), 0.0);  // in every image
  // Fewer descriptors than k.
  std::mt19937 rng(1);
  v.train({random_prototypes(3, rng)}, params);
  EXPECT_EQ(v.size(), 3u);
}
