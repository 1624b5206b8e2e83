// Deterministic, richly textured grayscale images (shapes at many scales over smooth
// noise) for feature tests and benchmarks that must not depend on dataset files.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>

namespace edge_slam {

// CV_8UC1 image of the given size; the same (size, seed) always gives the same pixels.
cv::Mat make_synthetic_texture(const cv::Size& size, uint64_t seed = 1);

}  // namespace edge_slam
