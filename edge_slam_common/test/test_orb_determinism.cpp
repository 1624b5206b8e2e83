// Same image -> bit-identical output, also when several threads share one extractor.
#include <gtest/gtest.h>

#include <thread>

#include "edge_slam/feature/orb_extractor.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

namespace {

struct Features {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

void expect_identical(const Features& a, const Features& b) {
  ASSERT_EQ(a.keypoints.size(), b.keypoints.size());
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    EXPECT_EQ(a.keypoints[i].pt, b.keypoints[i].pt);
    EXPECT_EQ(a.keypoints[i].angle, b.keypoints[i].angle);
    EXPECT_EQ(a.keypoints[i].octave, b.keypoints[i].octave);
    EXPECT_EQ(a.keypoints[i].response, b.keypoints[i].response);
    EXPECT_EQ(a.keypoints[i].size, b.keypoints[i].size);
  }
  ASSERT_EQ(a.descriptors.size(), b.descriptors.size());
  EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_HAMMING), 0.0);
}

}  // namespace

TEST(OrbDeterminism, RepeatedExtractionIsIdentical) {
  const cv::Mat image = make_synthetic_texture(cv::Size(640, 480), 5);
  const OrbExtractor extractor;
  Features first, second;
  extractor.extract(image, first.keypoints, first.descriptors);
  extractor.extract(image.clone(), second.keypoints, second.descriptors);
  ASSERT_GT(first.keypoints.size(), 500u);
  expect_identical(first, second);
  // A separately constructed extractor agrees too.
  Features third;
  OrbExtractor(OrbParams()).extract(image, third.keypoints, third.descriptors);
  expect_identical(first, third);
}

// The extractor keeps its pyramid and smoothed levels from call to call (per thread): nothing
// of one image may leak into the next, whatever its content or size.
TEST(OrbDeterminism, AlternatingImagesAndSizesGiveEachItsOwnResult) {
  const cv::Mat large = make_synthetic_texture(cv::Size(640, 480), 31);
  const cv::Mat small = make_synthetic_texture(cv::Size(320, 240), 32);
  Features large_alone, small_alone;
  OrbExtractor(OrbParams()).extract(large, large_alone.keypoints, large_alone.descriptors);
  std::thread([&] { OrbExtractor(OrbParams()).extract(small, small_alone.keypoints, small_alone.descriptors); })
      .join();  // a fresh thread: no buffers from before
  const OrbExtractor extractor;
  for (int round = 0; round < 3; ++round) {
    Features a, b;
    extractor.extract(small, b.keypoints, b.descriptors);
    extractor.extract(large, a.keypoints, a.descriptors);
    expect_identical(large_alone, a);
    expect_identical(small_alone, b);
  }
}

TEST(OrbDeterminism, ConcurrentThreadsAgreeWithSerialResult) {
  const cv::Mat image_a = make_synthetic_texture(cv::Size(640, 480), 21);
  const cv::Mat image_b = make_synthetic_texture(cv::Size(640, 480), 22);
  const OrbExtractor extractor;
  Features serial_a, serial_b;
  extractor.extract(image_a, serial_a.keypoints, serial_a.descriptors);
  extractor.extract(image_b, serial_b.keypoints, serial_b.descriptors);

  constexpr int kRounds = 5;
  std::vector<Features> from_a(kRounds), from_b(kRounds);
  std::thread worker_a([&] {
    for (Features& f : from_a) extractor.extract(image_a, f.keypoints, f.descriptors);
  });
  std::thread worker_b([&] {
    for (Features& f : from_b) extractor.extract(image_b, f.keypoints, f.descriptors);
  });
  worker_a.join();
  worker_b.join();
  for (int i = 0; i < kRounds; ++i) {
    expect_identical(serial_a, from_a[i]);
    expect_identical(serial_b, from_b[i]);
  }
}

TEST(OrbDeterminism, SyntheticTextureIsReproducible) {
  const cv::Mat a = make_synthetic_texture(cv::Size(320, 240), 9);
  const cv::Mat b = make_synthetic_texture(cv::Size(320, 240), 9);
  const cv::Mat c = make_synthetic_texture(cv::Size(320, 240), 10);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 0.0);
}
