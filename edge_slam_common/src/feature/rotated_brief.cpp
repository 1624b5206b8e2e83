#include "edge_slam/feature/rotated_brief.h"

#include <cmath>

#include "edge_slam/feature/brief_pattern.h"
#include "edge_slam/feature/descriptor_distance.h"

namespace edge_slam {

void compute_rotated_brief(const cv::Mat& smoothed, int x, int y, float angle_deg, uint8_t* descriptor) {
  const float angle = angle_deg * static_cast<float>(CV_PI / 180.0);
  const float c = std::cos(angle);
  const float s = std::sin(angle);
  const uint8_t* center = smoothed.ptr<uint8_t>(y) + x;
  const int step = static_cast<int>(smoothed.step1());
  // Image offset of pattern point (px, py) after rotation by the keypoint angle.
  auto rotated_offset = [&](int px, int py) {
    return cvRound(px * s + py * c) * step + cvRound(px * c - py * s);
  };

  const auto& pattern = brief_pattern();
  for (int byte = 0; byte < kDescriptorBytes; ++byte) {
    uint8_t bits = 0;
    for (int bit = 0; bit < 8; ++bit) {
      const BriefTest& t = pattern[byte * 8 + bit];
      const uint8_t first = center[rotated_offset(t.x1, t.y1)];
      const uint8_t second = center[rotated_offset(t.x2, t.y2)];
      bits |= static_cast<uint8_t>(first < second) << bit;
    }
    descriptor[byte] = bits;
  }
}

}  // namespace edge_slam
