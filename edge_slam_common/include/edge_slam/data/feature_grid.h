// Uniform grid (64 x 48 cells) over the undistorted image bounds, holding keypoint
// indices so that matching can fetch the keypoints near a pixel without a full scan.
#pragma once
#include <opencv2/core/types.hpp>
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
  // to pyramid levels [min_level, max_level] (a negative bound means unrestricted).
  std::vector<size_t> in_area(const std::vector<cv::KeyPoint>& keys_un, float x, float y, float r,
                              int min_level = -1, int max_level = -1) const;

  const ImageBounds& bounds() const { return bounds_; }

 private:
  bool cell_of(const cv::KeyPoint& kp, int& col, int& row) const;
  ImageBounds bounds_;
  float inv_cell_w_ = 0, inv_cell_h_ = 0;
  std::vector<std::vector<size_t>> cells_;  // row-major kRows x kCols
};

}  // namespace edge_slam
