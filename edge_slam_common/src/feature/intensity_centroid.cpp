#include "edge_slam/feature/intensity_centroid.h"

#include <cmath>

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
  float angle = static_cast<float>(std::atan2(static_cast<double>(m01), static_cast<double>(m10)) * (180.0 / CV_PI));
  if (angle < 0.0f) angle += 360.0f;
  if (angle >= 360.0f) angle = 0.0f;  // -tiny + 360 can round up to 360 in float
  return angle;
}

}  // namespace edge_slam
