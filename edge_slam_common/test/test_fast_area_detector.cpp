// fast_corners_in_area (our SIMD + scalar FAST for small areas) against cv::FAST on the area
// grown by 3 px, the call it replaces: identical corners, scores, fields and order, on noise,
// smooth ramps, flat images and the synthetic ORB texture, at both extractor thresholds and
// for areas narrower than a SIMD block, touching the 3-px margin and of every odd size.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "edge_slam/feature/fast_area_detector.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

namespace {

std::vector<cv::KeyPoint> reference(const cv::Mat& image, const cv::Rect& area, int threshold) {
  const cv::Rect search(area.x - 3, area.y - 3, area.width + 6, area.height + 6);
  std::vector<cv::KeyPoint> found;
  cv::FAST(image(search), found, threshold, true);
  for (cv::KeyPoint& kp : found) {
    kp.pt.x += static_cast<float>(search.x);
    kp.pt.y += static_cast<float>(search.y);
  }
  return found;
}

void expect_same(const std::vector<cv::KeyPoint>& got, const std::vector<cv::KeyPoint>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].pt, want[i].pt) << what << " corner " << i;
    ASSERT_EQ(got[i].response, want[i].response) << what << " corner " << i;
    ASSERT_EQ(got[i].size, want[i].size);
    ASSERT_EQ(got[i].angle, want[i].angle);
    ASSERT_EQ(got[i].octave, want[i].octave);
    ASSERT_EQ(got[i].class_id, want[i].class_id);
  }
}

std::vector<cv::Mat> test_images() {
  std::mt19937 rng(21);
  std::vector<cv::Mat> images;
  cv::Mat noise(120, 160, CV_8UC1);
  cv::randu(noise, 0, 256);
  images.push_back(noise);
  cv::Mat soft;
  cv::GaussianBlur(noise, soft, cv::Size(5, 5), 1.2);  // low contrast: the retry threshold's regime
  images.push_back(soft);
  cv::Mat blobs(120, 160, CV_8UC1, cv::Scalar(128));
  for (int i = 0; i < 60; ++i)
    cv::circle(blobs, cv::Point(rng() % 160, rng() % 120), 1 + rng() % 4, cv::Scalar(rng() % 256), -1);
  images.push_back(blobs);
  cv::Mat ramp(120, 160, CV_8UC1);
  for (int y = 0; y < ramp.rows; ++y)
    for (int x = 0; x < ramp.cols; ++x) ramp.at<uint8_t>(y, x) = static_cast<uint8_t>((x * 3 + y * 2) % 256);
  images.push_back(ramp);
  images.push_back(cv::Mat(120, 160, CV_8UC1, cv::Scalar(0)));
  images.push_back(cv::Mat(120, 160, CV_8UC1, cv::Scalar(255)));
  images.push_back(make_synthetic_texture(cv::Size(160, 120), 4));
  return images;
}

}  // namespace

TEST(FastAreaDetector, SameCornersAsCvFastOnTheGrownArea) {
  std::mt19937 rng(4);
  size_t total = 0;
  for (const cv::Mat& image : test_images()) {
    for (int threshold : {7, 20, 0, 40}) {
      for (int trial = 0; trial < 60; ++trial) {
        const int w = 1 + static_cast<int>(rng() % 50), h = 1 + static_cast<int>(rng() % 40);
        const int x = 3 + static_cast<int>(rng() % (image.cols - 6 - w + 1));
        const int y = 3 + static_cast<int>(rng() % (image.rows - 6 - h + 1));
        const cv::Rect area(x, y, w, h);
        std::vector<cv::KeyPoint> got;
        fast_corners_in_area(image, area, threshold, got);
        const std::vector<cv::KeyPoint> want = reference(image, area, threshold);
        expect_same(got, want, "area " + std::to_string(x) + "," + std::to_string(y) + " " + std::to_string(w) + "x" +
                                   std::to_string(h) + " threshold " + std::to_string(threshold));
        total += want.size();
      }
    }
  }
  EXPECT_GT(total, 2000u);  // the comparison saw plenty of corners
}

TEST(FastAreaDetector, AppendsAndIgnoresEmptyAreas) {
  const cv::Mat image = make_synthetic_texture(cv::Size(160, 120), 4);
  std::vector<cv::KeyPoint> out(3);
  fast_corners_in_area(image, cv::Rect(10, 10, 0, 5), 7, out);
  EXPECT_EQ(out.size(), 3u);
  fast_corners_in_area(image, cv::Rect(3, 3, 154, 114), 7, out);
  EXPECT_EQ(out.size(), 3 + reference(image, cv::Rect(3, 3, 154, 114), 7).size());
}
