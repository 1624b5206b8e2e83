#include "edge_slam/feature/rotated_brief.h"

#include <cmath>
#include <opencv2/core/hal/intrin.hpp>

#include "edge_slam/feature/brief_pattern.h"
#include "edge_slam/feature/descriptor_distance.h"

namespace edge_slam {
namespace {

constexpr int kPatternPoints = 2 * kBriefTests;

// The pattern as separate x / y float arrays (test i uses points 2i and 2i + 1), laid out
// so the per-keypoint rotation runs four points per SIMD instruction.
struct PatternPoints {
  alignas(16) float x[kPatternPoints];
  alignas(16) float y[kPatternPoints];
  PatternPoints() {
    const auto& pattern = brief_pattern();
    for (int i = 0; i < kBriefTests; ++i) {
      x[2 * i] = pattern[i].x1;
      y[2 * i] = pattern[i].y1;
      x[2 * i + 1] = pattern[i].x2;
      y[2 * i + 1] = pattern[i].y2;
    }
  }
};

const PatternPoints& pattern_points() {
  static const PatternPoints points;  // thread-safe one-time initialisation
  return points;
}

// offsets[k] = image offset of pattern point k rotated by (c, s), rounded to the nearest
// pixel (ties to even, like cvRound).
void rotated_offsets(float c, float s, int step, int* offsets) {
  const PatternPoints& p = pattern_points();
#if CV_SIMD128
  const cv::v_float32x4 vc = cv::v_setall_f32(c), vs = cv::v_setall_f32(s);
  const cv::v_int32x4 vstep = cv::v_setall_s32(step);
  for (int k = 0; k < kPatternPoints; k += 4) {
    const cv::v_float32x4 px = cv::v_load_aligned(p.x + k), py = cv::v_load_aligned(p.y + k);
    const cv::v_int32x4 rx = cv::v_round(px * vc - py * vs);
    const cv::v_int32x4 ry = cv::v_round(px * vs + py * vc);
    cv::v_store(offsets + k, ry * vstep + rx);
  }
#else
  for (int k = 0; k < kPatternPoints; ++k)
    offsets[k] = cvRound(p.x[k] * s + p.y[k] * c) * step + cvRound(p.x[k] * c - p.y[k] * s);
#endif
}

}  // namespace

void compute_rotated_brief(const cv::Mat& smoothed, int x, int y, float angle_deg, uint8_t* descriptor) {
  const float angle = angle_deg * static_cast<float>(CV_PI / 180.0);
  int offsets[kPatternPoints];
  rotated_offsets(std::cos(angle), std::sin(angle), static_cast<int>(smoothed.step1()), offsets);

  const uint8_t* center = smoothed.ptr<uint8_t>(y) + x;
  const int* pair = offsets;
  for (int byte = 0; byte < kDescriptorBytes; ++byte) {
    uint8_t bits = 0;
    for (int bit = 0; bit < 8; ++bit, pair += 2)
      bits |= static_cast<uint8_t>(center[pair[0]] < center[pair[1]]) << bit;
    descriptor[byte] = bits;
  }
}

}  // namespace edge_slam
