// FeatureGrid (flat, compressed-row layout) against a brute-force scan over every keypoint:
// the same indices, in the order the matcher relies on (cells row-major, then keypoint
// index), for random queries with and without level limits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "edge_slam/data/feature_grid.h"

using namespace edge_slam;

namespace {

// The grid's contract spelled out naively: a keypoint lives in the cell its rounded scaled
// position falls in (none outside the 64 x 48 cells); a query lists, ordered by (row, col,
// index), those within the square and the level range.
std::vector<size_t> brute_force(const std::vector<cv::KeyPoint>& keys, const ImageBounds& b, float x, float y,
                                float r, int min_level, int max_level) {
  const float inv_w = FeatureGrid::kCols / (b.max_x - b.min_x), inv_h = FeatureGrid::kRows / (b.max_y - b.min_y);
  std::vector<std::tuple<int, int, size_t>> hits;
  for (size_t i = 0; i < keys.size(); ++i) {
    const cv::KeyPoint& k = keys[i];
    const int col = static_cast<int>(std::round((k.pt.x - b.min_x) * inv_w));
    const int row = static_cast<int>(std::round((k.pt.y - b.min_y) * inv_h));
    if (col < 0 || col >= FeatureGrid::kCols || row < 0 || row >= FeatureGrid::kRows) continue;
    if ((min_level > 0 || max_level >= 0) && (k.octave < min_level || (max_level >= 0 && k.octave > max_level)))
      continue;
    if (std::fabs(k.pt.x - x) < r && std::fabs(k.pt.y - y) < r) hits.emplace_back(row, col, i);
  }
  std::sort(hits.begin(), hits.end());
  std::vector<size_t> out;
  for (const auto& h : hits) out.push_back(std::get<2>(h));
  return out;
}

std::vector<cv::KeyPoint> random_keys(std::mt19937& rng, const ImageBounds& b, int n) {
  std::uniform_real_distribution<float> ux(b.min_x - 5, b.max_x + 5), uy(b.min_y - 5, b.max_y + 5);
  std::uniform_int_distribution<int> level(0, 7);
  std::vector<cv::KeyPoint> keys;
  for (int i = 0; i < n; ++i) {
    cv::KeyPoint k(ux(rng), uy(rng), 31.f);
    k.octave = level(rng);
    keys.push_back(k);
  }
  // Clusters: many keypoints in one cell, and exact duplicates.
  for (int i = 0; i < 40; ++i) keys.push_back(cv::KeyPoint(100.2f + 0.1f * (i % 5), 200.7f, 31.f, -1, 0, i % 8));
  // Octaves outside the usual 0-7 (records from elsewhere): they must still be found exactly.
  for (int i = 0; i < 30; ++i) {
    cv::KeyPoint k(ux(rng), uy(rng), 31.f);
    k.octave = i % 3 == 0 ? -2 : i % 3 == 1 ? 12 : 40;
    keys.push_back(k);
  }
  return keys;
}

}  // namespace

TEST(FeatureGrid, MatchesBruteForceScanInOrder) {
  std::mt19937 rng(5);
  const ImageBounds bounds{-12.5f, 651.f, -9.f, 488.5f};  // undistorted fr1-like borders
  const std::vector<cv::KeyPoint> keys = random_keys(rng, bounds, 1500);
  const FeatureGrid grid(keys, bounds);
  std::uniform_real_distribution<float> ux(bounds.min_x - 20, bounds.max_x + 20), uy(bounds.min_y - 20, bounds.max_y + 20);
  std::uniform_real_distribution<float> ur(0.f, 60.f);
  std::uniform_int_distribution<int> level(-3, 14);
  std::vector<size_t> got;
  size_t non_empty = 0;
  for (int q = 0; q < 3000; ++q) {
    const float x = q % 10 == 0 ? 100.3f : ux(rng), y = q % 10 == 0 ? 200.7f : uy(rng);
    const float r = q % 50 == 0 ? 400.f : ur(rng);
    const int lo = level(rng), hi = q % 3 == 0 ? -1 : level(rng);
    grid.in_area(x, y, r, lo, hi, got);
    const std::vector<size_t> want = brute_force(keys, bounds, x, y, r, lo, hi);
    ASSERT_EQ(got, want) << "query " << q << " at (" << x << ", " << y << ") r " << r << " levels " << lo << ".." << hi;
    non_empty += want.empty() ? 0 : 1;
  }
  EXPECT_GT(non_empty, 1000u);  // the comparison must have exercised real hits
  // The allocating form answers the same.
  EXPECT_EQ(grid.in_area(keys, 100.3f, 200.7f, 3.f), brute_force(keys, bounds, 100.3f, 200.7f, 3.f, -1, -1));
}

TEST(FeatureGrid, ReusedBufferIsClearedAndBadQueriesAreEmpty) {
  std::mt19937 rng(9);
  const ImageBounds bounds{0.f, 640.f, 0.f, 480.f};
  const std::vector<cv::KeyPoint> keys = random_keys(rng, bounds, 500);
  const FeatureGrid grid(keys, bounds);
  std::vector<size_t> out;
  grid.in_area(320.f, 240.f, 100.f, -1, -1, out);
  ASSERT_FALSE(out.empty());
  grid.in_area(NAN, 240.f, 5.f, -1, -1, out);
  EXPECT_TRUE(out.empty());
  grid.in_area(320.f, 240.f, -1.f, -1, -1, out);
  EXPECT_TRUE(out.empty());
  grid.in_area(5000.f, 240.f, 5.f, -1, -1, out);
  EXPECT_TRUE(out.empty());
  FeatureGrid empty;
  empty.in_area(320.f, 240.f, 100.f, -1, -1, out);
  EXPECT_TRUE(out.empty());
  // Keypoints rounded outside the last column/row are not in the grid, as before.
  EXPECT_LT(grid.size(), keys.size());
}
