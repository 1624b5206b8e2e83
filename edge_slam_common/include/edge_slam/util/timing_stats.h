// Summary statistics of per-frame timings (mean, median, 95th percentile, max).
#pragma once
#include <cstddef>
#include <vector>

namespace edge_slam {

struct TimingStats {
  double mean = 0, median = 0, p95 = 0, max = 0;
  size_t count = 0;
};

TimingStats summarize_times(std::vector<double> values_ms);

}  // namespace edge_slam
