// Timings summarised as they come, in a fixed amount of memory: for processes that run for
// hours (the mobile tracks 30 frames a second; a vector of every frame's time grows by 8 bytes a
// frame, ~7 MB in a working day, for a median nobody reads before the end).
// Count, mean, max and the last value are exact; median and p95 are the nearest rank's bin, whose
// width is 1% of its value, so they are within 0.5% of what summarize_times gives on the values
// (for an even count the median is the lower middle value, where summarize_times averages two).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

#include "edge_slam/util/timing_stats.h"

namespace edge_slam {

class TimingHistogram {
 public:
  // Values below kMinMs share the first bin, values above kMaxMs the last (max stays exact).
  static constexpr double kMinMs = 1e-3, kMaxMs = 1e6, kBinRatio = 1.01;
  static constexpr size_t kBins = 2084;  // ceil(log(kMaxMs / kMinMs) / log(kBinRatio)) + 1

  void add(double ms);  // NaN and negative values are ignored (not timings)
  TimingStats stats() const;
  size_t count() const { return static_cast<size_t>(count_); }
  double last() const { return last_; }  // 0 before any value

 private:
  double quantile(double q) const;  // nearest rank, as summarize_times

  std::array<uint32_t, kBins> bins_{};
  uint64_t count_ = 0;
  double sum_ = 0, min_ = 0, max_ = 0, last_ = 0;
};

}  // namespace edge_slam
