#include "edge_slam/util/timing_histogram.h"

#include <algorithm>
#include <cmath>

namespace edge_slam {
namespace {

size_t bin_of(double ms) {
  if (!(ms > TimingHistogram::kMinMs)) return 0;
  const double i = std::floor(std::log(ms / TimingHistogram::kMinMs) / std::log(TimingHistogram::kBinRatio));
  return static_cast<size_t>(std::min(i, static_cast<double>(TimingHistogram::kBins - 1)));
}

}  // namespace

void TimingHistogram::add(double ms) {
  if (!(ms >= 0)) return;
  ++bins_[bin_of(ms)];
  min_ = count_ ? std::min(min_, ms) : ms;
  max_ = count_ ? std::max(max_, ms) : ms;
  ++count_;
  sum_ += ms;
  last_ = ms;
}

double TimingHistogram::quantile(double q) const {
  const uint64_t rank = std::max<uint64_t>(1, static_cast<uint64_t>(std::ceil(q * count_)));
  uint64_t seen = 0;
  for (size_t i = 0; i < kBins; ++i) {
    seen += bins_[i];
    if (seen >= rank) {
      if (i == kBins - 1) return max_;  // the overflow bin has no upper edge
      // The bin's geometric middle, kept within the values seen (a lone value comes back exact
      // when it is the smallest or the largest).
      const double mid = kMinMs * std::pow(kBinRatio, static_cast<double>(i) + 0.5);
      return std::clamp(mid, min_, max_);
    }
  }
  return max_;
}

TimingStats TimingHistogram::stats() const {
  TimingStats s;
  s.count = static_cast<size_t>(count_);
  if (count_ == 0) return s;
  s.mean = sum_ / count_;
  s.median = quantile(0.5);
  s.p95 = quantile(0.95);
  s.max = max_;
  return s;
}

}  // namespace edge_slam
