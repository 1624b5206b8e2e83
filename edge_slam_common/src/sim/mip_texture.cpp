#include "edge_slam/sim/mip_texture.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edge_slam {

MipTexture::MipTexture(const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC3)
    throw std::invalid_argument("MipTexture needs a non-empty CV_8UC3 image");
  levels_.push_back(image.clone());
  while (levels_.back().cols > 4 && levels_.back().rows > 4) {
    cv::Mat half;
    cv::pyrDown(levels_.back(), half);
    levels_.push_back(half);
  }
}

cv::Vec3f MipTexture::bilinear(int lvl, double x, double y) const {
  const cv::Mat& img = levels_[lvl];
  const double scale = 1.0 / static_cast<double>(1 << lvl);
  // Texel centres sit at integer + 0.5 in level-0 units.
  const double fx = std::clamp(x * scale - 0.5, 0.0, img.cols - 1.0);
  const double fy = std::clamp(y * scale - 0.5, 0.0, img.rows - 1.0);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const int x1 = std::min(x0 + 1, img.cols - 1), y1 = std::min(y0 + 1, img.rows - 1);
  const float ax = static_cast<float>(fx - x0), ay = static_cast<float>(fy - y0);
  const cv::Vec3b* r0 = img.ptr<cv::Vec3b>(y0);
  const cv::Vec3b* r1 = img.ptr<cv::Vec3b>(y1);
  cv::Vec3f out;
  for (int c = 0; c < 3; ++c) {
    const float top = r0[x0][c] + ax * (r0[x1][c] - r0[x0][c]);
    const float bottom = r1[x0][c] + ax * (r1[x1][c] - r1[x0][c]);
    out[c] = top + ay * (bottom - top);
  }
  return out;
}

cv::Vec3f MipTexture::sample(double x, double y, double level) const {
  const double top = static_cast<double>(levels_.size() - 1);
  level = std::clamp(level, 0.0, top);
  const int l0 = static_cast<int>(level);
  const float a = static_cast<float>(level - l0);
  const cv::Vec3f c0 = bilinear(l0, x, y);
  if (a < 1e-3f || l0 >= static_cast<int>(top)) return c0;
  return c0 * (1.0f - a) + bilinear(l0 + 1, x, y) * a;
}

}  // namespace edge_slam
