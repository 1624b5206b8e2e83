// FAST corners over a grid of cells so that weakly textured areas still get candidates:
// cells where the normal threshold finds nothing are searched again with a lower one.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

struct FastGridParams {
  int cell_size = 30;        // target cell side (pixels); the grid is stretched to fit exactly
  int border = 19;           // no corner closer than this to the image border
  int ini_threshold = 20;
  int min_threshold = 7;
};

// Region (in image pixels) in which detect_fast_in_grid can return corners; empty if the
// image is too small to keep `border` pixels free on every side.
cv::Rect fast_detection_area(const cv::Size& image_size, int border);

// image: CV_8UC1. Returns corners (non-maximum suppressed, response = FAST score) inside
// fast_detection_area(image.size(), params.border), in image coordinates.
std::vector<cv::KeyPoint> detect_fast_in_grid(const cv::Mat& image, const FastGridParams& params);

}  // namespace edge_slam
