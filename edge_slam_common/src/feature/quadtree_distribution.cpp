#include "edge_slam/feature/quadtree_distribution.h"

#include <algorithm>
#include <cmath>

namespace edge_slam {
namespace {

// A cell owns the contiguous slice [begin, end) of a shared index array; splitting
// partitions that slice in place, so no per-cell allocations are needed.
struct Cell {
  float x0, y0, x1, y1;
  int begin, end;
  int count() const { return end - begin; }
};

// Below this side length two distinct integer pixel positions cannot share a cell,
// so a smaller cell can only hold duplicates: stop splitting it.
constexpr float kMinCellSide = 0.5f;

bool can_split(const Cell& cell) {
  return cell.count() > 1 && (cell.x1 - cell.x0 > kMinCellSide || cell.y1 - cell.y0 > kMinCellSide);
}

// Appends the non-empty quadrants of `cell` to `out`.
void split_cell(const Cell& cell, const std::vector<cv::KeyPoint>& kps, std::vector<int>& order,
                std::vector<Cell>& out) {
  const float mx = 0.5f * (cell.x0 + cell.x1);
  const float my = 0.5f * (cell.y0 + cell.y1);
  auto first = order.begin() + cell.begin;
  auto last = order.begin() + cell.end;
  auto left = [&](int i) { return kps[i].pt.x < mx; };
  auto top = [&](int i) { return kps[i].pt.y < my; };
  auto mid_x = std::partition(first, last, left);
  auto mid_top_left = std::partition(first, mid_x, top);
  auto mid_top_right = std::partition(mid_x, last, top);
  auto offset = [&](std::vector<int>::iterator it) { return static_cast<int>(it - order.begin()); };
  const Cell quadrants[4] = {
      {cell.x0, cell.y0, mx, my, cell.begin, offset(mid_top_left)},
      {cell.x0, my, mx, cell.y1, offset(mid_top_left), offset(mid_x)},
      {mx, cell.y0, cell.x1, my, offset(mid_x), offset(mid_top_right)},
      {mx, my, cell.x1, cell.y1, offset(mid_top_right), cell.end},
  };
  for (const Cell& q : quadrants)
    if (q.count() > 0) out.push_back(q);
}

// Roughly square root cells tile the region, so splits halve cells along both axes evenly.
// Fills `order` with keypoint indices grouped by root cell (a counting sort).
std::vector<Cell> root_cells(const std::vector<cv::KeyPoint>& kps, const cv::Rect2f& region,
                             std::vector<int>& order) {
  const float w = std::max(region.width, 1.0f);
  const float h = std::max(region.height, 1.0f);
  const int cols = std::max(1, static_cast<int>(std::lround(w / h)));
  const int rows = std::max(1, static_cast<int>(std::lround(h / w)));
  std::vector<int> root_of(kps.size());
  std::vector<int> first_of_root(static_cast<size_t>(cols) * rows + 1, 0);
  for (size_t i = 0; i < kps.size(); ++i) {
    const int c = std::clamp(static_cast<int>((kps[i].pt.x - region.x) * cols / w), 0, cols - 1);
    const int r = std::clamp(static_cast<int>((kps[i].pt.y - region.y) * rows / h), 0, rows - 1);
    root_of[i] = r * cols + c;
    ++first_of_root[root_of[i] + 1];
  }
  for (size_t k = 1; k < first_of_root.size(); ++k) first_of_root[k] += first_of_root[k - 1];
  order.resize(kps.size());
  std::vector<int> next_slot(first_of_root.begin(), first_of_root.end() - 1);
  for (size_t i = 0; i < kps.size(); ++i) order[next_slot[root_of[i]]++] = static_cast<int>(i);

  std::vector<Cell> roots;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int id = r * cols + c;
      if (first_of_root[id] == first_of_root[id + 1]) continue;
      roots.push_back({region.x + c * w / cols, region.y + r * h / rows, region.x + (c + 1) * w / cols,
                       region.y + (r + 1) * h / rows, first_of_root[id], first_of_root[id + 1]});
    }
  }
  return roots;
}

}  // namespace

std::vector<cv::KeyPoint> distribute_quadtree(const std::vector<cv::KeyPoint>& kps, const cv::Rect2f& region,
                                              int target) {
  std::vector<cv::KeyPoint> kept;
  if (target <= 0 || kps.empty()) return kept;

  std::vector<int> order;
  std::vector<Cell> cells = root_cells(kps, region, order);

  // Breadth-first rounds keep cells of similar size, which is what spreads the keypoints.
  // Within a round the most crowded cells go first, so if the target is reached mid-round
  // the remaining crowding is where it matters least.
  const size_t wanted = static_cast<size_t>(target);
  std::vector<Cell> next;
  std::vector<size_t> splittable;
  while (cells.size() < wanted) {
    splittable.clear();
    for (size_t i = 0; i < cells.size(); ++i)
      if (can_split(cells[i])) splittable.push_back(i);
    if (splittable.empty()) break;
    std::stable_sort(splittable.begin(), splittable.end(),
                     [&](size_t a, size_t b) { return cells[a].count() > cells[b].count(); });

    std::vector<char> was_split(cells.size(), 0);
    next.clear();
    size_t total = cells.size();
    for (size_t i : splittable) {
      const size_t before = next.size();
      split_cell(cells[i], kps, order, next);
      was_split[i] = 1;
      total += next.size() - before - 1;
      if (total >= wanted) break;
    }
    for (size_t i = 0; i < cells.size(); ++i)
      if (!was_split[i]) next.push_back(cells[i]);
    cells.swap(next);
  }

  kept.reserve(cells.size());
  for (const Cell& cell : cells) {
    int best = order[cell.begin];
    for (int k = cell.begin + 1; k < cell.end; ++k)
      if (kps[order[k]].response > kps[best].response) best = order[k];
    kept.push_back(kps[best]);
  }
  // The last split of a round can overshoot by up to 3 cells: drop the weakest extras.
  if (kept.size() > wanted) {
    std::nth_element(kept.begin(), kept.begin() + target, kept.end(),
                     [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
    kept.resize(wanted);
  }
  return kept;
}

}  // namespace edge_slam
