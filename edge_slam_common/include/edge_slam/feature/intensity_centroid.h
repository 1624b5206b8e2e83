// Keypoint orientation from the intensity centroid of a disc around it (Rosin's moments):
// the angle of the vector from the keypoint to the centroid of the patch brightness.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

// half_widths[v] = largest u with u^2 + v^2 <= radius^2, for v = 0..radius: the row
// extents of a digital disc. The disc is symmetric in u and v by construction.
std::vector<int> disc_half_widths(int radius);

// Angle in degrees, [0, 360), of the intensity centroid of the disc described by
// half_widths around pixel (x, y) of `image` (CV_8UC1). The caller guarantees the disc
// fits inside the image.
float intensity_centroid_angle(const cv::Mat& image, int x, int y, const std::vector<int>& half_widths);

}  // namespace edge_slam
