// Per-level scale factors and measurement uncertainties of the ORB image pyramid,
// shared (immutably) by every Frame and KeyFrame extracted with the same settings.
#pragma once
#include <cmath>
#include <vector>

namespace edge_slam {

struct ScalePyramid {
  int num_levels = 1;
  float scale_factor = 1.2f;
  float log_scale_factor = std::log(1.2f);
  std::vector<float> scale_factors{1.f};
  std::vector<float> inv_scale_factors{1.f};
  std::vector<float> level_sigma2{1.f};
  std::vector<float> inv_level_sigma2{1.f};

  static ScalePyramid make(int num_levels, float scale_factor) {
    ScalePyramid p;
    p.num_levels = num_levels;
    p.scale_factor = scale_factor;
    p.log_scale_factor = std::log(scale_factor);
    p.scale_factors.assign(num_levels, 1.f);
    for (int i = 1; i < num_levels; ++i) p.scale_factors[i] = p.scale_factors[i - 1] * scale_factor;
    p.inv_scale_factors.resize(num_levels);
    p.level_sigma2.resize(num_levels);
    p.inv_level_sigma2.resize(num_levels);
    for (int i = 0; i < num_levels; ++i) {
      p.inv_scale_factors[i] = 1.f / p.scale_factors[i];
      p.level_sigma2[i] = p.scale_factors[i] * p.scale_factors[i];
      p.inv_level_sigma2[i] = 1.f / p.level_sigma2[i];
    }
    return p;
  }

  // Pyramid level at which a point at distance `dist` should be observed, given that
  // it is seen at level 0 up to `max_distance` (ORB-SLAM2's scale prediction).
  int predict_level(double max_distance, double dist) const {
    // Clamped in floating point: a degenerate range (0, negative, NaN, e.g. from a corrupt
    // record) must not reach the int conversion as +-inf or NaN.
    if (!(dist > 0)) return 0;
    const double level = std::ceil(std::log(max_distance / dist) / log_scale_factor);
    if (!(level > 0)) return 0;
    if (level >= num_levels - 1) return num_levels - 1;
    return static_cast<int>(level);
  }
};

}  // namespace edge_slam
