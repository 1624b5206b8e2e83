#include "edge_slam/data/feature_grid.h"

#include <algorithm>
#include <cmath>

namespace edge_slam {

FeatureGrid::FeatureGrid(const std::vector<cv::KeyPoint>& keys_un, const ImageBounds& bounds)
    : bounds_(bounds), cells_(kCols * kRows) {
  const float w = bounds.max_x - bounds.min_x;
  const float h = bounds.max_y - bounds.min_y;
  inv_cell_w_ = w > 0 ? kCols / w : 0.f;
  inv_cell_h_ = h > 0 ? kRows / h : 0.f;
  for (size_t i = 0; i < keys_un.size(); ++i) {
    int c, r;
    if (cell_of(keys_un[i], c, r)) cells_[r * kCols + c].push_back(i);
  }
}

bool FeatureGrid::cell_of(const cv::KeyPoint& kp, int& col, int& row) const {
  col = static_cast<int>(std::round((kp.pt.x - bounds_.min_x) * inv_cell_w_));
  row = static_cast<int>(std::round((kp.pt.y - bounds_.min_y) * inv_cell_h_));
  return col >= 0 && col < kCols && row >= 0 && row < kRows;
}

std::vector<size_t> FeatureGrid::in_area(const std::vector<cv::KeyPoint>& keys_un, float x,
                                         float y, float r, int min_level, int max_level) const {
  std::vector<size_t> out;
  if (cells_.empty() || !(r >= 0) || !std::isfinite(x) || !std::isfinite(y)) return out;
  const int c0 = std::max(0, static_cast<int>(std::floor((x - bounds_.min_x - r) * inv_cell_w_)));
  const int c1 = std::min(kCols - 1, static_cast<int>(std::ceil((x - bounds_.min_x + r) * inv_cell_w_)));
  const int r0 = std::max(0, static_cast<int>(std::floor((y - bounds_.min_y - r) * inv_cell_h_)));
  const int r1 = std::min(kRows - 1, static_cast<int>(std::ceil((y - bounds_.min_y + r) * inv_cell_h_)));
  if (c0 > c1 || r0 > r1) return out;
  const bool check_levels = min_level > 0 || max_level >= 0;
  for (int row = r0; row <= r1; ++row) {
    for (int col = c0; col <= c1; ++col) {
      for (size_t idx : cells_[row * kCols + col]) {
        const cv::KeyPoint& kp = keys_un[idx];
        if (check_levels) {
          if (kp.octave < min_level) continue;
          if (max_level >= 0 && kp.octave > max_level) continue;
        }
        if (std::fabs(kp.pt.x - x) < r && std::fabs(kp.pt.y - y) < r) out.push_back(idx);
      }
    }
  }
  return out;
}

}  // namespace edge_slam
