#include "edge_slam/feature/intensity_centroid.h"

#include <cmath>
#include <cstdlib>
#include <opencv2/core/hal/intrin.hpp>

namespace edge_slam {

std::vector<int> disc_half_widths(int radius) {
  std::vector<int> half_widths(radius + 1);
  for (int v = 0; v <= radius; ++v) {
    int u = static_cast<int>(std::sqrt(static_cast<double>(radius * radius - v * v)));
    // Guard the integer boundary against sqrt rounding either way.
    while (u * u + v * v > radius * radius) --u;
    while ((u + 1) * (u + 1) + v * v <= radius * radius) ++u;
    half_widths[v] = u;
  }
  return half_widths;
}

namespace {

// Degrees in [0, 360) of the moments' direction.
float moments_angle(int m10, int m01) {
  float angle = static_cast<float>(std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * (180.0 / CV_PI));
  if (angle < 0.0f) angle += 360.0f;
  if (angle >= 360.0f) angle = 0.0f;  // -tiny + 360 can round up to 360 in float
  return angle;
}

}  // namespace

CentroidDisc::CentroidDisc(int radius) : radius_(radius), half_widths_(disc_half_widths(radius)) {
  if (radius > 15) return;  // no table: the scalar loop serves it
  u_weight_.assign(static_cast<size_t>(radius + 1) * kLanes, 0);
  inside_.assign(static_cast<size_t>(radius + 1) * kLanes, 0);
  for (int v = 0; v <= radius; ++v)
    for (int lane = 0; lane < kLanes; ++lane) {
      const int u = lane - kLanes / 2;
      if (std::abs(u) > half_widths_[v]) continue;
      u_weight_[v * kLanes + lane] = static_cast<int16_t>(u);
      inside_[v * kLanes + lane] = 1;
    }
}

float CentroidDisc::angle(const cv::Mat& image, int x, int y) const {
#if CV_SIMD128
  if (!u_weight_.empty()) {
    // Lanes cover u = -16..15 (lane 0 and u = 16 carry weight 0), two 16-byte loads per row.
    const uint8_t* center = image.ptr<uint8_t>(y) + x - kLanes / 2;
    const int step = static_cast<int>(image.step1());
    cv::v_int32x4 m10 = cv::v_setzero_s32();
    int m01 = 0;
    auto widen = [](const uint8_t* p, cv::v_int16x8 out[4]) {
      cv::v_uint16x8 a, b;
      cv::v_expand(cv::v_load(p), a, b);
      out[0] = cv::v_reinterpret_as_s16(a);
      out[1] = cv::v_reinterpret_as_s16(b);
      cv::v_expand(cv::v_load(p + 16), a, b);
      out[2] = cv::v_reinterpret_as_s16(a);
      out[3] = cv::v_reinterpret_as_s16(b);
    };
    cv::v_int16x8 row[4], below[4], above[4];
    widen(center, row);
    for (int k = 0; k < 4; ++k) m10 += cv::v_dotprod(row[k], cv::v_load(u_weight_.data() + 8 * k));
    for (int v = 1; v <= radius_; ++v) {
      widen(center + v * step, below);
      widen(center - v * step, above);
      const int16_t* wu = u_weight_.data() + v * kLanes;
      const int16_t* in = inside_.data() + v * kLanes;
      cv::v_int32x4 diff = cv::v_setzero_s32();
      for (int k = 0; k < 4; ++k) {
        // Rows +v and -v share u: their sum feeds m10, their difference m01 (values fit int16).
        m10 += cv::v_dotprod(below[k] + above[k], cv::v_load(wu + 8 * k));
        diff += cv::v_dotprod(below[k] - above[k], cv::v_load(in + 8 * k));
      }
      m01 += v * cv::v_reduce_sum(diff);
    }
    return moments_angle(cv::v_reduce_sum(m10), m01);
  }
#endif
  return intensity_centroid_angle(image, x, y, half_widths_);
}

float intensity_centroid_angle(const cv::Mat& image, int x, int y, const std::vector<int>& half_widths) {
  const uint8_t* center = image.ptr<uint8_t>(y) + x;
  const int step = static_cast<int>(image.step1());
  int m10 = 0;  // sum of u * I
  int m01 = 0;  // sum of v * I
  const int r0 = half_widths[0];
  for (int u = -r0; u <= r0; ++u) m10 += u * center[u];
  // Rows +v and -v share u, so one pass covers both: their sum feeds m10, their difference m01.
  const int radius = static_cast<int>(half_widths.size()) - 1;
  for (int v = 1; v <= radius; ++v) {
    const uint8_t* below = center + v * step;
    const uint8_t* above = center - v * step;
    const int r = half_widths[v];
    int row_diff = 0;
    for (int u = -r; u <= r; ++u) {
      const int b = below[u];
      const int a = above[u];
      m10 += u * (b + a);
      row_diff += b - a;
    }
    m01 += v * row_diff;
  }
  return moments_angle(m10, m01);
}

}  // namespace edge_slam
