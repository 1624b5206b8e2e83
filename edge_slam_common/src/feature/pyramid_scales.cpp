#include "edge_slam/feature/pyramid_scales.h"

#include <algorithm>
#include <cmath>

namespace edge_slam {

PyramidScales make_pyramid_scales(float scale_factor, int num_levels) {
  PyramidScales s;
  double scale = 1.0;  // accumulate in double so high levels do not drift
  for (int level = 0; level < num_levels; ++level) {
    s.scale.push_back(static_cast<float>(scale));
    s.inv_scale.push_back(static_cast<float>(1.0 / scale));
    s.sigma2.push_back(static_cast<float>(scale * scale));
    s.inv_sigma2.push_back(static_cast<float>(1.0 / (scale * scale)));
    scale *= scale_factor;
  }
  return s;
}

std::vector<int> features_per_level(int num_features, float scale_factor, int num_levels) {
  std::vector<int> counts(std::max(num_levels, 0), 0);
  if (num_levels <= 0 || num_features <= 0) return counts;
  const double ratio = 1.0 / scale_factor;
  // First term of the geometric series whose num_levels terms sum to num_features.
  const double first = num_features * (1.0 - ratio) / (1.0 - std::pow(ratio, num_levels));
  // Rounding the running total (not each term) keeps every count >= 0 and the sum exact;
  // whatever rounding leaves over lands on the coarsest level.
  double cumulative = 0.0;
  double term = first;
  int assigned = 0;
  for (int level = 0; level + 1 < num_levels; ++level) {
    cumulative += term;
    const int rounded_total = std::min(static_cast<int>(std::lround(cumulative)), num_features);
    counts[level] = rounded_total - assigned;
    assigned = rounded_total;
    term *= ratio;
  }
  counts[num_levels - 1] = num_features - assigned;
  return counts;
}

}  // namespace edge_slam
