#include "edge_slam/data/feature_grid.h"

#include <algorithm>
#include <cmath>

namespace edge_slam {

FeatureGrid::FeatureGrid(const std::vector<cv::KeyPoint>& keys_un, const ImageBounds& bounds)
    : bounds_(bounds), cell_start_(kCols * kRows + 1, 0) {
  const float w = bounds.max_x - bounds.min_x;
  const float h = bounds.max_y - bounds.min_y;
  inv_cell_w_ = w > 0 ? kCols / w : 0.f;
  inv_cell_h_ = h > 0 ? kRows / h : 0.f;
  // Counting sort by cell: count, prefix-sum, then place in index order, so each cell
  // lists its keypoints by increasing index (the order the per-cell vectors had).
  std::vector<int> cell(keys_un.size(), -1);
  for (size_t i = 0; i < keys_un.size(); ++i) {
    int c, r;
    if (cell_of(keys_un[i].pt, c, r)) {
      cell[i] = r * kCols + c;
      ++cell_start_[cell[i] + 1];
    }
  }
  for (size_t k = 1; k < cell_start_.size(); ++k) cell_start_[k] += cell_start_[k - 1];
  entries_.resize(cell_start_.back());
  std::vector<uint32_t> next(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < keys_un.size(); ++i) {
    if (cell[i] < 0) continue;
    const cv::KeyPoint& kp = keys_un[i];
    entries_[next[cell[i]]++] = Entry{kp.pt.x, kp.pt.y, kp.octave, static_cast<uint32_t>(i)};
  }
}

bool FeatureGrid::cell_of(const cv::Point2f& pt, int& col, int& row) const {
  col = static_cast<int>(std::round((pt.x - bounds_.min_x) * inv_cell_w_));
  row = static_cast<int>(std::round((pt.y - bounds_.min_y) * inv_cell_h_));
  return col >= 0 && col < kCols && row >= 0 && row < kRows;
}

void FeatureGrid::in_area(float x, float y, float r, int min_level, int max_level, std::vector<size_t>& out) const {
  out.clear();
  if (cell_start_.empty() || !(r >= 0) || !std::isfinite(x) || !std::isfinite(y)) return;
  const int c0 = std::max(0, static_cast<int>(std::floor((x - bounds_.min_x - r) * inv_cell_w_)));
  const int c1 = std::min(kCols - 1, static_cast<int>(std::ceil((x - bounds_.min_x + r) * inv_cell_w_)));
  const int r0 = std::max(0, static_cast<int>(std::floor((y - bounds_.min_y - r) * inv_cell_h_)));
  const int r1 = std::min(kRows - 1, static_cast<int>(std::ceil((y - bounds_.min_y + r) * inv_cell_h_)));
  if (c0 > c1 || r0 > r1) return;
  const bool check_levels = min_level > 0 || max_level >= 0;
  for (int row = r0; row <= r1; ++row) {
    // Cells c0..c1 of a row are adjacent in entries_: one run.
    const Entry* e = entries_.data() + cell_start_[row * kCols + c0];
    const Entry* const end = entries_.data() + cell_start_[row * kCols + c1 + 1];
    for (; e != end; ++e) {
      if (check_levels) {
        if (e->octave < min_level) continue;
        if (max_level >= 0 && e->octave > max_level) continue;
      }
      if (std::fabs(e->x - x) < r && std::fabs(e->y - y) < r) out.push_back(e->index);
    }
  }
}

std::vector<size_t> FeatureGrid::in_area(const std::vector<cv::KeyPoint>& /*keys_un*/, float x, float y, float r,
                                         int min_level, int max_level) const {
  std::vector<size_t> out;
  in_area(x, y, r, min_level, max_level, out);
  return out;
}

}  // namespace edge_slam
