// Per-level scale tables of an ORB image pyramid and the per-level feature budget.
#pragma once
#include <vector>

namespace edge_slam {

struct PyramidScales {
  std::vector<float> scale;          // scale_factor^level: 1, s, s^2, ...
  std::vector<float> inv_scale;      // 1 / scale
  std::vector<float> sigma2;         // scale^2: keypoint position variance grows with the level
  std::vector<float> inv_sigma2;     // 1 / sigma2
};

PyramidScales make_pyramid_scales(float scale_factor, int num_levels);

// Splits num_features over the levels proportionally to each level's side length
// (1/s^level), i.e. a geometric series summing exactly to num_features; rounding
// leftovers go to the coarsest level.
std::vector<int> features_per_level(int num_features, float scale_factor, int num_levels);

}  // namespace edge_slam
