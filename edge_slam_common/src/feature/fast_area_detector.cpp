#include "edge_slam/feature/fast_area_detector.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <opencv2/core/hal/intrin.hpp>

namespace edge_slam {
namespace {

constexpr int kCirclePoints = 16;
constexpr int kArc = 9;  // contiguous circle pixels a corner needs
// Bresenham circle of radius 3, clockwise from the top, as (dx, dy). Only the cyclic order
// matters: the segment test and the score look at contiguous arcs.
constexpr int kCircle[kCirclePoints][2] = {{0, -3}, {1, -3},  {2, -2},  {3, -1}, {3, 0},   {3, 1},  {2, 2},  {1, 3},
                                           {0, 3},  {-1, 3}, {-2, 2}, {-3, 1}, {-3, 0}, {-3, -1}, {-2, -2}, {-1, -3}};

// True when the 16-bit cyclic mask has a run of at least 9 set bits.
bool has_arc(uint32_t mask) {
  const uint32_t m = mask | (mask << kCirclePoints);
  uint32_t run = m;
  for (int i = 1; i < kArc; ++i) run &= m >> i;
  return (run & 0xffffu) != 0;
}

bool is_corner(const uint8_t* p, const int* offsets, int threshold) {
  const int v = p[0];
  uint32_t bright = 0, dark = 0;
  for (int k = 0; k < kCirclePoints; ++k) {
    const int x = p[offsets[k]];
    bright |= static_cast<uint32_t>(x > v + threshold) << k;
    dark |= static_cast<uint32_t>(x < v - threshold) << k;
  }
  return has_arc(bright) || has_arc(dark);
}

// The FAST score of a corner: the largest threshold it would still pass, minus 1, i.e.
// max over the 16 arcs of 9 of (min of v - x over the arc, or -max of v - x), minus 1.
int corner_score(const uint8_t* p, const int* offsets) {
  const int v = p[0];
  int16_t d[kCirclePoints + 8];  // the circle and its first 8 again: every arc is contiguous
  for (int k = 0; k < kCirclePoints + 8; ++k) d[k] = static_cast<int16_t>(v - p[offsets[k % kCirclePoints]]);
#if CV_SIMD128
  // Lanes = arc starts 0..7 and 8..15; 9 shifted loads give each arc's min and max.
  cv::v_int16x8 lo0 = cv::v_load(d), hi0 = lo0, lo1 = cv::v_load(d + 8), hi1 = lo1;
  for (int k = 1; k < kArc; ++k) {
    const cv::v_int16x8 a = cv::v_load(d + k), b = cv::v_load(d + 8 + k);  // up to d[23]
    lo0 = cv::v_min(lo0, a);
    hi0 = cv::v_max(hi0, a);
    lo1 = cv::v_min(lo1, b);
    hi1 = cv::v_max(hi1, b);
  }
  const int darker = cv::v_reduce_max(cv::v_max(lo0, lo1));
  const int brighter = cv::v_reduce_min(cv::v_min(hi0, hi1));
#else
  int darker = INT_MIN, brighter = INT_MAX;  // best arc of darker (v - x > 0) / brighter pixels
  for (int s = 0; s < kCirclePoints; ++s) {
    int lo = d[s], hi = d[s];
    for (int k = s + 1; k < s + kArc; ++k) {
      lo = std::min<int>(lo, d[k]);
      hi = std::max<int>(hi, d[k]);
    }
    darker = std::max(darker, lo);
    brighter = std::min(brighter, hi);
  }
#endif
  return std::max(darker, -brighter) - 1;
}

#if CV_SIMD128
// Corner flags of the 16 pixels starting at p (0xff = corner): the segment test on 16 lanes.
// Returns false when no lane is a corner.
bool corner_lanes(const uint8_t* p, const int* offsets, const cv::v_uint8x16& t, uint8_t flags[16]) {
  const cv::v_uint8x16 v = cv::v_load(p);
  // Unsigned order through the sign bit: x > v + t  <=>  (x ^ 0x80) > ((v + t) ^ 0x80) as signed.
  const cv::v_int8x16 bias = cv::v_setall_s8(-128);
  const cv::v_int8x16 hi = cv::v_reinterpret_as_s8(v + t) ^ bias;  // saturating: nothing exceeds 255
  const cv::v_int8x16 lo = cv::v_reinterpret_as_s8(v - t) ^ bias;  // saturating: nothing is below 0
  cv::v_int8x16 b[kCirclePoints], d[kCirclePoints];
  // Any 9-arc contains two neighbouring compass points (0/4, 4/8, 8/12, 12/0): test those first.
  for (int k = 0; k < kCirclePoints; k += 4) {
    const cv::v_int8x16 x = cv::v_reinterpret_as_s8(cv::v_load(p + offsets[k])) ^ bias;
    b[k] = x > hi;
    d[k] = x < lo;
  }
  const cv::v_int8x16 maybe = (b[0] & b[4]) | (b[4] & b[8]) | (b[8] & b[12]) | (b[12] & b[0]) | (d[0] & d[4]) |
                              (d[4] & d[8]) | (d[8] & d[12]) | (d[12] & d[0]);
  if (!cv::v_check_any(maybe)) return false;
  for (int k = 0; k < kCirclePoints; ++k) {
    if (k % 4 == 0) continue;
    const cv::v_int8x16 x = cv::v_reinterpret_as_s8(cv::v_load(p + offsets[k])) ^ bias;
    b[k] = x > hi;
    d[k] = x < lo;
  }
  // A run of 9 starting at k: pairs, then quadruples, then eight, then the ninth.
  cv::v_int8x16 b2[kCirclePoints], d2[kCirclePoints], b4[kCirclePoints], d4[kCirclePoints];
  for (int k = 0; k < kCirclePoints; ++k) {
    b2[k] = b[k] & b[(k + 1) % kCirclePoints];
    d2[k] = d[k] & d[(k + 1) % kCirclePoints];
  }
  for (int k = 0; k < kCirclePoints; ++k) {
    b4[k] = b2[k] & b2[(k + 2) % kCirclePoints];
    d4[k] = d2[k] & d2[(k + 2) % kCirclePoints];
  }
  cv::v_int8x16 corner = cv::v_setzero_s8();
  for (int k = 0; k < kCirclePoints; ++k) {
    const int k4 = (k + 4) % kCirclePoints, k8 = (k + 8) % kCirclePoints;
    corner = corner | (b4[k] & b4[k4] & b[k8]) | (d4[k] & d4[k4] & d[k8]);
  }
  if (!cv::v_check_any(corner)) return false;
  cv::v_store(reinterpret_cast<int8_t*>(flags), corner);
  return true;
}
#endif

}  // namespace

void fast_corners_in_area(const cv::Mat& image, const cv::Rect& area, int threshold, std::vector<cv::KeyPoint>& out) {
  if (area.width <= 0 || area.height <= 0) return;
  threshold = std::clamp(threshold, 0, 255);
  const int step = static_cast<int>(image.step1());
  int offsets[kCirclePoints];
  for (int k = 0; k < kCirclePoints; ++k) offsets[k] = kCircle[k][0] + kCircle[k][1] * step;

  // Scores of the corners (0 elsewhere) with a ring of zeros around: the neighbours outside
  // the area, which cv::FAST never evaluates for a sub-image, count 0 in the suppression.
  const int w = area.width, h = area.height, sw = w + 2;
  thread_local std::vector<uint8_t> scores;
  scores.assign(static_cast<size_t>(sw) * (h + 2), 0);
  auto score_at = [&](int x, int y) -> uint8_t& { return scores[static_cast<size_t>(y + 1) * sw + (x + 1)]; };

  // Corners in row-major order (the order cv::FAST reports them in), for the suppression.
  thread_local std::vector<cv::Point> corners;
  corners.clear();
  auto add_corner = [&](const uint8_t* p, int x, int y) {
    score_at(x, y) = static_cast<uint8_t>(corner_score(p, offsets));
    corners.emplace_back(x, y);
  };
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = image.ptr<uint8_t>(area.y + y) + area.x;
    int x = 0;
#if CV_SIMD128
    const cv::v_uint8x16 t = cv::v_setall_u8(static_cast<uint8_t>(threshold));
    uint8_t flags[16];
    // Blocks of 16; the last one is moved back to end at the area's edge, and its lanes
    // already seen are skipped.
    for (; w >= 16 && x < w; x += 16) {
      const int x0 = std::min(x, w - 16);
      if (!corner_lanes(row + x0, offsets, t, flags)) continue;
      for (int k = x - x0; k < 16; ++k)
        if (flags[k]) add_corner(row + x0 + k, x0 + k, y);
    }
#endif
    for (; x < w; ++x)
      if (is_corner(row + x, offsets, threshold)) add_corner(row + x, x, y);
  }

  for (const cv::Point& c : corners) {
    const int x = c.x, y = c.y;
    const uint8_t s = score_at(x, y);
    // (A corner of score 0 never beats its neighbours, as in cv::FAST.)
    if (s > score_at(x - 1, y - 1) && s > score_at(x, y - 1) && s > score_at(x + 1, y - 1) && s > score_at(x - 1, y) &&
        s > score_at(x + 1, y) && s > score_at(x - 1, y + 1) && s > score_at(x, y + 1) && s > score_at(x + 1, y + 1))
      out.emplace_back(static_cast<float>(area.x + x), static_cast<float>(area.y + y), 7.f, -1.f, static_cast<float>(s));
  }
}

}  // namespace edge_slam
