// Spreads keypoints evenly over an image region: the region is recursively split into
// quadrants until there are as many non-empty cells as wanted keypoints (or no cell holds
// more than one keypoint), then each cell keeps only its strongest keypoint.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

// Returns at most `target` keypoints (fewer only if fewer were given), each the strongest
// response of its cell. Keypoints outside `region` are clamped into the border cells.
std::vector<cv::KeyPoint> distribute_quadtree(const std::vector<cv::KeyPoint>& keypoints,
                                              const cv::Rect2f& region, int target);

}  // namespace edge_slam
