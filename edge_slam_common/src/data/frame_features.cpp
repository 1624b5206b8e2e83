#include "edge_slam/data/frame_features.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace edge_slam {
namespace {

cv::Mat camera_matrix(const PinholeCamera& c) {
  return (cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
}
cv::Mat distortion(const PinholeCamera& c) {
  return (cv::Mat_<double>(1, 5) << c.k1, c.k2, c.p1, c.p2, c.k3);
}

std::vector<cv::Point2f> undistort(const PinholeCamera& cam, const std::vector<cv::Point2f>& pts) {
  if (pts.empty() || !cam.has_distortion()) return pts;
  std::vector<cv::Point2f> out;
  const cv::Mat K = camera_matrix(cam);
  cv::undistortPoints(pts, out, K, distortion(cam), cv::noArray(), K);
  return out;
}

float depth_at(const cv::Mat& depth_image, const cv::Point2f& pt, double depth_factor) {
  if (depth_image.empty()) return -1.f;
  const int u = static_cast<int>(std::lround(pt.x));
  const int v = static_cast<int>(std::lround(pt.y));
  if (u < 0 || v < 0 || u >= depth_image.cols || v >= depth_image.rows) return -1.f;
  float z = -1.f;
  if (depth_image.type() == CV_16UC1) {
    z = static_cast<float>(depth_image.at<uint16_t>(v, u) / depth_factor);
  } else if (depth_image.type() == CV_32FC1) {
    z = depth_image.at<float>(v, u);
  }
  return (std::isfinite(z) && z > 0.f) ? z : -1.f;
}

}  // namespace

ImageBounds compute_image_bounds(const PinholeCamera& cam) {
  ImageBounds b;
  if (!cam.has_distortion()) {
    b.max_x = static_cast<float>(cam.width);
    b.max_y = static_cast<float>(cam.height);
    return b;
  }
  const float w = static_cast<float>(cam.width), h = static_cast<float>(cam.height);
  const auto c = undistort(cam, {{0, 0}, {w, 0}, {0, h}, {w, h}});
  b.min_x = std::min(c[0].x, c[2].x);
  b.max_x = std::max(c[1].x, c[3].x);
  b.min_y = std::min(c[0].y, c[1].y);
  b.max_y = std::max(c[2].y, c[3].y);
  return b;
}

std::shared_ptr<const FrameFeatures> FrameFeatures::build(const PinholeCamera& camera,
                                                          std::shared_ptr<const ScalePyramid> pyramid,
                                                          std::vector<cv::KeyPoint> keys,
                                                          cv::Mat descriptors,
                                                          const cv::Mat& depth_image) {
  if (!pyramid) throw std::invalid_argument("FrameFeatures::build: no scale pyramid");
  if (descriptors.rows != static_cast<int>(keys.size()) ||
      (!keys.empty() && (descriptors.type() != CV_8U || descriptors.cols != 32)))
    throw std::invalid_argument("FrameFeatures::build: descriptors must be N x 32 CV_8U, got " +
                                std::to_string(descriptors.rows) + " x " +
                                std::to_string(descriptors.cols) + " for " +
                                std::to_string(keys.size()) + " keypoints");
  auto f = std::make_shared<FrameFeatures>();
  f->camera = camera;
  f->pyramid = std::move(pyramid);
  f->keys = std::move(keys);
  f->descriptors = descriptors.isContinuous() ? descriptors : descriptors.clone();

  std::vector<cv::Point2f> raw(f->keys.size());
  for (size_t i = 0; i < f->keys.size(); ++i) raw[i] = f->keys[i].pt;
  const auto und = undistort(camera, raw);
  f->keys_un = f->keys;
  for (size_t i = 0; i < und.size(); ++i) f->keys_un[i].pt = und[i];

  f->depth.assign(f->keys.size(), -1.f);
  f->right_x.assign(f->keys.size(), -1.f);
  for (size_t i = 0; i < f->keys.size(); ++i) {
    const float z = depth_at(depth_image, f->keys[i].pt, camera.depth_factor);
    if (z > 0.f) {
      f->depth[i] = z;
      f->right_x[i] = static_cast<float>(f->keys_un[i].pt.x - camera.bf / z);
    }
  }
  f->bounds = compute_image_bounds(camera);
  f->grid = FeatureGrid(f->keys_un, f->bounds);
  return f;
}

}  // namespace edge_slam
