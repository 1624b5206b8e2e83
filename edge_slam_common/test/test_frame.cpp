#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "edge_slam/data/frame.h"
#include "edge_slam/feature/orb_extractor.h"
#include "edge_slam/feature/synthetic_texture.h"

using namespace edge_slam;

namespace {
PinholeCamera camera() {
  PinholeCamera c = synthetic_room_camera(30.0);
  c.name = "test";
  c.fx = c.fy = 500;
  c.th_depth = 3.2;
  return c;
}
std::shared_ptr<ScalePyramid> pyramid() { return std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f)); }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Frame, RejectsWrongSizesAndTypes) {
  const OrbExtractor orb;
  const PinholeCamera cam = camera();
  const cv::Mat gray(480, 640, CV_8UC1, cv::Scalar(0));
  const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(0));
  EXPECT_NE(error_of([&] { Frame::from_rgbd(0, 0, cv::Mat(), depth, cam, orb); }).find("empty"), std::string::npos);
  EXPECT_NE(error_of([&] { Frame::from_rgbd(0, 0, cv::Mat(240, 320, CV_8UC1), cv::Mat(240, 320, CV_16UC1), cam, orb); })
                .find("320x240"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Frame::from_rgbd(0, 0, cv::Mat(480, 640, CV_16UC1), depth, cam, orb); }).find("8-bit"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Frame::from_rgbd(0, 0, gray, cv::Mat(480, 640, CV_8UC1), cam, orb); }).find("depth"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Frame::from_rgbd(0, 0, gray, cv::Mat(480, 320, CV_16UC1), cam, orb); }).find("depth"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Frame::from_rgbd(0, 0, gray, cv::Mat(), cam, orb); }).find("depth"), std::string::npos);
}

TEST(Frame, TexturelessImageGivesNoKeypoints) {
  const OrbExtractor orb;
  const Frame f = Frame::from_rgbd(0, 0, cv::Mat(480, 640, CV_8UC3, cv::Scalar(90, 90, 90)),
                                   cv::Mat(480, 640, CV_16UC1, cv::Scalar(10000)), camera(), orb);
  EXPECT_EQ(f.size(), 0u);
  EXPECT_EQ(f.num_matched(), 0);
}

TEST(Frame, MissingDepthIsNanZeroOrNegative) {
  const std::vector<cv::KeyPoint> keys = {cv::KeyPoint(10, 10, 31), cv::KeyPoint(20, 10, 31),
                                          cv::KeyPoint(30, 10, 31), cv::KeyPoint(400, 10, 31),
                                          cv::KeyPoint(50, 10, 31)};
  cv::Mat desc(5, 32, CV_8U, cv::Scalar(1));
  cv::Mat d32(480, 640, CV_32FC1, cv::Scalar(0));
  d32.at<float>(10, 10) = std::nanf("");
  d32.at<float>(10, 20) = 0.f;
  d32.at<float>(10, 30) = -1.f;
  d32.at<float>(10, 400) = 2.0f;
  d32.at<float>(10, 50) = 5.0f;
  auto f = FrameFeatures::build(camera(), pyramid(), keys, desc, d32);
  EXPECT_FALSE(f->has_depth(0));
  EXPECT_FALSE(f->has_depth(1));
  EXPECT_FALSE(f->has_depth(2));
  ASSERT_TRUE(f->has_depth(3));
  EXPECT_FLOAT_EQ(f->depth[3], 2.0f);
  EXPECT_NEAR(f->right_x[3], 400 - camera().bf / 2.0, 1e-4);  // u - bf / z
  EXPECT_LT(f->right_x[0], 0);
  EXPECT_TRUE(f->is_close(3));
  EXPECT_FALSE(f->is_close(4));  // 5 m > th_depth 3.2 m
  EXPECT_TRUE(f->has_depth(4));

  cv::Mat d16(480, 640, CV_16UC1, cv::Scalar(0));
  d16.at<uint16_t>(10, 400) = 10000;  // 2 m at factor 5000
  auto g = FrameFeatures::build(camera(), pyramid(), keys, desc, d16);
  EXPECT_FALSE(g->has_depth(0));
  EXPECT_FLOAT_EQ(g->depth[3], 2.0f);
  const Eigen::Vector3d p = g->unproject_camera(3);
  EXPECT_NEAR(p.z(), 2.0, 1e-6);
  EXPECT_NEAR(p.x(), (400 - 319.5) * 2.0 / 500, 1e-6);
}

TEST(Frame, ExtractsGridsAndUndistorts) {
  const OrbExtractor orb;
  const cv::Mat img = make_synthetic_texture(cv::Size(640, 480), 11);
  cv::Mat color;
  cv::cvtColor(img, color, cv::COLOR_GRAY2BGR);
  const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(7500));  // 1.5 m
  Frame f = Frame::from_rgbd(3, 1.5, color, depth, camera(), orb);
  ASSERT_GT(f.size(), 500u);
  EXPECT_EQ(f.id, 3u);
  EXPECT_EQ(f.map_points.size(), f.size());
  for (size_t i = 0; i < f.size(); i += 50) {
    const cv::KeyPoint& k = f.feat().keys_un[i];
    const auto near = f.features_in_area(k.pt.x, k.pt.y, 2.f);
    EXPECT_NE(std::find(near.begin(), near.end(), i), near.end());
    const auto same_level = f.features_in_area(k.pt.x, k.pt.y, 2.f, k.octave, k.octave);
    EXPECT_NE(std::find(same_level.begin(), same_level.end(), i), same_level.end());
    const auto other_level = f.features_in_area(k.pt.x, k.pt.y, 2.f, k.octave + 1, k.octave + 3);
    EXPECT_EQ(std::find(other_level.begin(), other_level.end(), i), other_level.end());
    EXPECT_FLOAT_EQ(f.feat().depth[i], 1.5f);
    EXPECT_FLOAT_EQ(f.feat().keys[i].pt.x, k.pt.x);  // no distortion
  }

  PinholeCamera distorted = camera();
  distorted.k1 = 0.262383;  // TUM freiburg1
  distorted.k2 = -0.953104;
  distorted.p1 = -0.005358;
  distorted.p2 = 0.002628;
  distorted.k3 = 1.163314;
  Frame g = Frame::from_rgbd(4, 1.6, color, depth, distorted, orb);
  ASSERT_GT(g.size(), 0u);
  const ImageBounds b = g.feat().bounds;
  EXPECT_GT(b.min_x, 1.f);
  EXPECT_LT(b.max_x, 639.f);
  double moved = 0;
  for (size_t i = 0; i < g.size(); ++i)
    moved = std::max(moved, cv::norm(g.feat().keys[i].pt - g.feat().keys_un[i].pt));
  EXPECT_GT(moved, 1.0);
}
