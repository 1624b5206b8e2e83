#include "edge_slam/feature/fast_grid_detector.h"

#include <algorithm>
#include <opencv2/features2d.hpp>

#include "edge_slam/feature/fast_area_detector.h"

namespace edge_slam {
namespace {

// cv::FAST never reports corners within 3 px of the border of the image it is given,
// because the Bresenham circle has radius 3.
constexpr int kFastCircleRadius = 3;

// Runs FAST on `area` grown by the circle radius, so corners can lie anywhere in `area`;
// returns them in full-image coordinates.
void fast_in_area(const cv::Mat& image, const cv::Rect& area, int threshold, std::vector<cv::KeyPoint>& out) {
  const cv::Rect search(area.x - kFastCircleRadius, area.y - kFastCircleRadius,
                        area.width + 2 * kFastCircleRadius, area.height + 2 * kFastCircleRadius);
  std::vector<cv::KeyPoint> found;
  cv::FAST(image(search), found, threshold, /*nonmaxSuppression=*/true);
  for (cv::KeyPoint& kp : found) {
    kp.pt.x += static_cast<float>(search.x);
    kp.pt.y += static_cast<float>(search.y);
    out.push_back(kp);
  }
}

}  // namespace

cv::Rect fast_detection_area(const cv::Size& image_size, int border) {
  // Keeping `border` >= the FAST radius guarantees the grown search window fits in the image.
  const int b = std::max(border, kFastCircleRadius);
  const int width = image_size.width - 2 * b;
  const int height = image_size.height - 2 * b;
  if (width <= 0 || height <= 0) return cv::Rect();
  return cv::Rect(b, b, width, height);
}

std::vector<cv::KeyPoint> detect_fast_in_grid(const cv::Mat& image, const FastGridParams& params) {
  std::vector<cv::KeyPoint> corners;
  const cv::Rect area = fast_detection_area(image.size(), params.border);
  if (image.empty() || area.empty()) return corners;

  // One pass over the whole area at the normal threshold (cheaper than one FAST call per
  // cell, and non-maximum suppression is not cut at cell edges) ...
  fast_in_area(image, area, params.ini_threshold, corners);

  const int cell = std::max(params.cell_size, 1);
  const int cols = std::max(1, (area.width + cell / 2) / cell);
  const int rows = std::max(1, (area.height + cell / 2) / cell);
  auto cell_x0 = [&](int c) { return area.x + c * area.width / cols; };
  auto cell_y0 = [&](int r) { return area.y + r * area.height / rows; };

  std::vector<int> per_cell(static_cast<size_t>(cols) * rows, 0);
  for (const cv::KeyPoint& kp : corners) {
    const int c = std::min(cols - 1, (static_cast<int>(kp.pt.x) - area.x) * cols / area.width);
    const int r = std::min(rows - 1, (static_cast<int>(kp.pt.y) - area.y) * rows / area.height);
    ++per_cell[static_cast<size_t>(r) * cols + c];
  }

  // ... then a lower-threshold retry in the cells that came back empty.
  if (params.min_threshold >= params.ini_threshold) return corners;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (per_cell[static_cast<size_t>(r) * cols + c] > 0) continue;
      const cv::Rect cell_area(cell_x0(c), cell_y0(r), cell_x0(c + 1) - cell_x0(c), cell_y0(r + 1) - cell_y0(r));
      // The same corners as fast_in_area (cv::FAST on the grown cell) without its cost per
      // call, which for ~200 cells a frame outweighed the full-image pass.
      fast_corners_in_area(image, cell_area, params.min_threshold, corners);
    }
  }
  return corners;
}

}  // namespace edge_slam
