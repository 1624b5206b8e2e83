// TimingHistogram against summarize_times on the same values: count, mean and max exact, median
// and p95 within half a bin (0.5%), in fixed memory whatever the number of values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "edge_slam/util/timing_histogram.h"

namespace edge_slam {
namespace {

TEST(TimingHistogram, AgreesWithTheExactSummaryWithinHalfABin) {
  std::mt19937 rng(7);
  std::lognormal_distribution<double> tracking_like(std::log(10.0), 0.4);  // ~10 ms, a long tail
  std::vector<double> values;
  TimingHistogram h;
  for (int i = 0; i < 100001; ++i) {  // odd: the exact median is one value, as the histogram's
    const double ms = tracking_like(rng);
    values.push_back(ms);
    h.add(ms);
  }
  const TimingStats exact = summarize_times(values), approx = h.stats();
  EXPECT_EQ(approx.count, exact.count);
  EXPECT_NEAR(approx.mean, exact.mean, 1e-9 * exact.mean);
  EXPECT_EQ(approx.max, exact.max);
  EXPECT_NEAR(approx.median, exact.median, 0.005 * exact.median);
  EXPECT_NEAR(approx.p95, exact.p95, 0.005 * exact.p95);
  EXPECT_EQ(h.last(), values.back());
  EXPECT_LE(sizeof(TimingHistogram), 9000u) << "fixed, whatever the count";
}

TEST(TimingHistogram, EdgesAndNonTimings) {
  TimingHistogram h;
  EXPECT_EQ(h.stats().count, 0u);
  EXPECT_EQ(h.last(), 0.0);
  h.add(std::nan(""));
  h.add(-1.0);
  EXPECT_EQ(h.count(), 0u) << "not timings";
  h.add(0.0);  // below the first bin's edge: counted there, and exact as the minimum
  EXPECT_EQ(h.stats().median, 0.0);
  h.add(5e7);  // beyond the last bin: counted there, max exact
  h.add(5e7);
  const TimingStats s = h.stats();
  EXPECT_EQ(s.count, 3u);
  EXPECT_EQ(s.max, 5e7);
  EXPECT_EQ(s.p95, 5e7) << "clamped to the largest value seen";
  TimingHistogram one;
  one.add(12.345);
  EXPECT_EQ(one.stats().median, 12.345) << "a lone value comes back exact";
  EXPECT_EQ(one.stats().p95, 12.345);
}

}  // namespace
}  // namespace edge_slam
