// FAST-9 (16-pixel circle) corners with 3x3 non-maximum suppression inside a small area,
// giving exactly what cv::FAST(image(area grown by 3 px), corners, threshold, true) gives,
// without its fixed cost per call (threshold table, buffers, dispatch), which dominates for
// the ~200 small grid cells per frame that the extractor searches again at the low threshold.
//
// The contract, as cv::FAST has it: a pixel with value v is a corner at threshold t when at
// least 9 contiguous pixels of the circle are all > v + t or all < v - t; its score is
// max over the 16 arcs of 9 of (min of v - x over the arc, or -max of v - x) minus 1; it is
// kept when its score is greater than the scores of its 8 neighbours inside the area
// (neighbours that are no corner, or lie outside the area, count 0). Corners come in row-major
// order as KeyPoint(x, y, size 7, angle -1, response score), in image coordinates.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

// image: CV_8UC1; `area` must lie at least 3 pixels inside the image on every side (the
// circle's radius). Appends the corners to `out`.
void fast_corners_in_area(const cv::Mat& image, const cv::Rect& area, int threshold, std::vector<cv::KeyPoint>& out);

}  // namespace edge_slam
