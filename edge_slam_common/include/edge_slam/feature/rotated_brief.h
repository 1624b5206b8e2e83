// Steered BRIEF: the binary tests of brief_pattern() rotated by the keypoint angle, so the
// descriptor is (up to pixel rounding) invariant to in-plane rotation.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>

namespace edge_slam {

// smoothed: CV_8UC1 level image after Gaussian smoothing (single-pixel tests are too noisy
// otherwise). (x, y): keypoint pixel at least kOrbPatchRadius + 1 from every border.
// Writes kDescriptorBytes bytes; bit i of the descriptor is bit (i % 8) of byte i / 8.
void compute_rotated_brief(const cv::Mat& smoothed, int x, int y, float angle_deg, uint8_t* descriptor);

}  // namespace edge_slam
