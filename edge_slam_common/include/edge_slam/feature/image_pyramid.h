// Image pyramid with bilinear downsampling, each level resized from the previous one.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

// Returns one image per entry of inv_scale_factors (entry 0 must be 1: the input itself,
// not copied). Level n has size round(cols * inv_scale[n]) x round(rows * inv_scale[n]);
// a level that would be smaller than 1x1 and all coarser ones are left empty.
std::vector<cv::Mat> build_image_pyramid(const cv::Mat& gray, const std::vector<float>& inv_scale_factors);

// The same into `levels`, whose buffers are written over when a level keeps its size: a tracker
// that passes the same vector every frame allocates its pyramid once. The levels must not be
// shared with anyone who still reads them.
void build_image_pyramid_into(const cv::Mat& gray, const std::vector<float>& inv_scale_factors,
                              std::vector<cv::Mat>& levels);

}  // namespace edge_slam
