// Uniform grid (64 x 48 cells) over the undistorted image bounds, holding keypoint
// indices so that matching can fetch the keypoints near a pixel without a full scan.
// Stored flat (compressed rows): one array of entries sorted by cell, row-major, and the
// offset where each cell starts. Each entry carries its keypoint's position and level, so a
// query reads one contiguous run of memory per grid row instead of chasing a vector per
// cell and a cv::KeyPoint per candidate (this lookup runs ~10^4 times per tracked frame).
#pragma once
#include <opencv2/core/types.hpp>
#include <cstdint>
#include <vector>

namespace edge_slam {

struct ImageBounds {
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  bool contains(float x, float y) const { return x >= min_x && x < max_x && y >= min_y && y < max_y; }
};

class FeatureGrid {
 public:
  static constexpr int kCols = 64;
  static constexpr int kRows = 48;

  FeatureGrid() = default;
  FeatureGrid(const std::vector<cv::KeyPoint>& keys_un, const ImageBounds& bounds);

  // Indices of keypoints within a (2r x 2r) square around (x, y), optionally restricted
  // to pyramid levels [min_level, max_level] (a negative bound means unrestricted), written
  // to `out` (cleared first; callers reuse one buffer across queries). Order: cells
  // row-major, keypoint index within a cell.
  void in_area(float x, float y, float r, int min_level, int max_level, std::vector<size_t>& out) const;
  // The same, returning a new vector. `keys_un` must be the keypoints the grid was built
  // from (kept for the callers of the former interface; the grid answers from its own copy).
  std::vector<size_t> in_area(const std::vector<cv::KeyPoint>& keys_un, float x, float y, float r,
                              int min_level = -1, int max_level = -1) const;

  const ImageBounds& bounds() const { return bounds_; }
  size_t size() const { return entries_.size(); }  // keypoints inside the grid

 private:
  struct Entry {
    float x, y;
    int32_t octave;
    uint32_t index;
  };
  bool cell_of(const cv::Point2f& pt, int& col, int& row) const;
  ImageBounds bounds_;
  float inv_cell_w_ = 0, inv_cell_h_ = 0;
  std::vector<uint32_t> cell_start_;  // kRows * kCols + 1 offsets into entries_ (empty: no grid)
  std::vector<Entry> entries_;
};

}  // namespace edge_slam
