#include "edge_slam/util/timing_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace edge_slam {

TimingStats summarize_times(std::vector<double> v) {
  TimingStats s;
  s.count = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / v.size();
  const size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  // Nearest-rank percentile.
  const size_t rank = static_cast<size_t>(std::ceil(0.95 * n));
  s.p95 = v[std::min(n - 1, rank > 0 ? rank - 1 : 0)];
  s.max = v.back();
  return s;
}

}  // namespace edge_slam
