// StageClock / StageScope: exclusive per-stage accounting (a nested stage's time is not
// charged to the enclosing one), stages summing to the whole, scopes without a clock being
// no-ops, and clocks nesting per thread.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "edge_slam/util/stage_clock.h"

using namespace edge_slam;

namespace {

// Busy work: CPU time, which sleeping would not give.
void spin_ms(double ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double, std::milli>(ms);
  volatile double x = 0;
  while (std::chrono::steady_clock::now() < end) x = x + 1.0;
}

double sum(const std::array<double, kTrackingStages>& a) {
  double s = 0;
  for (double v : a) s += v;
  return s;
}

}  // namespace

TEST(StageClock, NestedStagesAreExclusiveAndAddUp) {
  const auto t0 = std::chrono::steady_clock::now();
  TrackingStageTimes t;
  {
    StageClock clock(TrackingStage::kExtract);
    spin_ms(20);
    {
      StageScope match(TrackingStage::kMatch);
      spin_ms(20);
      {
        StageScope pose(TrackingStage::kPose);
        spin_ms(120);
      }
      spin_ms(10);  // back in match
    }
    t = clock.read();
  }
  const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // Lower bounds hold whatever the load (the busy loops end on the wall clock); the nested
  // 120 ms must not show up in match (20 + 10), which a preemption of < 90 ms cannot fake.
  EXPECT_GE(t.wall(TrackingStage::kExtract), 20.0);
  EXPECT_GE(t.wall(TrackingStage::kMatch), 30.0);
  EXPECT_LT(t.wall(TrackingStage::kMatch), 120.0);
  EXPECT_GE(t.wall(TrackingStage::kPose), 120.0);
  EXPECT_EQ(t.wall(TrackingStage::kLocalMap), 0.0);
  EXPECT_LE(sum(t.wall_ms), total_ms + 0.01);
  // CPU: busy loops, so CPU time can only be lower than wall on a loaded machine, never higher.
  EXPECT_GT(t.cpu(TrackingStage::kPose), 0.0);
  EXPECT_LE(t.cpu(TrackingStage::kPose), t.wall(TrackingStage::kPose) + 1.0);
  EXPECT_EQ(StageClock::active(), nullptr);  // the clock uninstalled itself
}

TEST(StageClock, ScopeWithoutClockIsANoOpAndClocksNest) {
  EXPECT_EQ(StageClock::active(), nullptr);
  { StageScope nothing(TrackingStage::kPose); }  // must not crash
  StageClock outer(TrackingStage::kMatch);
  EXPECT_EQ(StageClock::active(), &outer);
  {
    StageClock inner(TrackingStage::kKeyFrame);
    EXPECT_EQ(StageClock::active(), &inner);
    spin_ms(5);
    EXPECT_GE(inner.read().wall(TrackingStage::kKeyFrame), 5.0);
  }
  EXPECT_EQ(StageClock::active(), &outer);
  // Another thread has no clock of its own.
  StageClock* seen = &outer;
  std::thread([&] { seen = StageClock::active(); }).join();
  EXPECT_EQ(seen, nullptr);
  EXPECT_EQ(outer.read().wall(TrackingStage::kKeyFrame), 0.0);
}

TEST(StageClock, StageNames) {
  EXPECT_STREQ(to_string(TrackingStage::kExtract), "extract");
  EXPECT_STREQ(to_string(TrackingStage::kLocalMap), "local_map");
  EXPECT_STREQ(to_string(TrackingStage::kKeyFrame), "keyframe");
}
