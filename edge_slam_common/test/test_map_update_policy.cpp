// Paper 4.4 / eq. 1: the Local-Map update acceptance rules and their counters.
#include <edge_slam/module/map_update_policy.h>
#include <gtest/gtest.h>

namespace edge_slam {
namespace {

TrackingSnapshot healthy(double now, double last_kf, int kfn) {
  TrackingSnapshot s;
  s.initialized = true;
  s.keyframe_since_last_update = true;
  s.now = now;
  s.last_keyframe_time = last_kf;
  s.local_map_keyframes = kfn;
  return s;
}

TEST(MapUpdatePolicy, TimeConstraintFollowsEquationOne) {
  MapUpdatePolicy p;  // ITC 300 ms, LMU 6
  EXPECT_DOUBLE_EQ(p.time_constraint(0), 0.3);
  EXPECT_DOUBLE_EQ(p.time_constraint(6), 0.15);
  EXPECT_DOUBLE_EQ(p.time_constraint(12), 0.1);
  EXPECT_NEAR(p.time_constraint(50), 0.3 / (50.0 / 6.0 + 1.0), 1e-12);
}

TEST(MapUpdatePolicy, EachRuleRejectsAndIsCounted) {
  MapUpdatePolicy p;
  EXPECT_EQ(p.decide(MapUpdateKind::kPeriodic, healthy(10.0, 9.0, 6)), UpdateDecision::kAccept);

  TrackingSnapshot s = healthy(10.0, 9.0, 6);
  s.initialized = false;
  EXPECT_EQ(p.decide(MapUpdateKind::kPeriodic, s), UpdateDecision::kRejectInitializing);

  s = healthy(10.0, 9.0, 6);
  s.keyframe_since_last_update = false;
  EXPECT_EQ(p.decide(MapUpdateKind::kPeriodic, s), UpdateDecision::kRejectRedundant);

  // TC(6) = 150 ms: a KeyFrame 100 ms ago blocks, 200 ms ago does not.
  EXPECT_EQ(p.decide(MapUpdateKind::kPeriodic, healthy(10.0, 9.9, 6)), UpdateDecision::kRejectKeyFrameRate);
  EXPECT_EQ(p.decide(MapUpdateKind::kPeriodic, healthy(10.0, 9.8, 6)), UpdateDecision::kAccept);

  p.set_enabled(false);
  EXPECT_EQ(p.decide(MapUpdateKind::kPeriodic, healthy(10.0, 1.0, 6)), UpdateDecision::kRejectController);
  p.set_enabled(true);
  p.count_invalid();

  const MapUpdateCounters& c = p.counters();
  EXPECT_EQ(c.received, 7u);
  EXPECT_EQ(c.accepted, 2u);
  EXPECT_EQ(c.rejected_initializing, 1u);
  EXPECT_EQ(c.rejected_redundant, 1u);
  EXPECT_EQ(c.rejected_keyframe_rate, 1u);
  EXPECT_EQ(c.rejected_controller, 1u);
  EXPECT_EQ(c.rejected_invalid, 1u);
}

TEST(MapUpdatePolicy, RelocalizationLiftsLimitsOnlyWhileLost) {
  MapUpdatePolicy p;
  TrackingSnapshot s = healthy(10.0, 9.99, 60);  // KeyFrame 10 ms ago, big Local-Map
  s.keyframe_since_last_update = false;
  s.lost = true;
  EXPECT_EQ(p.decide(MapUpdateKind::kRelocalization, s), UpdateDecision::kAccept);
  s.lost = false;
  EXPECT_EQ(p.decide(MapUpdateKind::kRelocalization, s), UpdateDecision::kRejectNotLost);
  p.set_enabled(false);
  s.lost = true;
  EXPECT_EQ(p.decide(MapUpdateKind::kRelocalization, s), UpdateDecision::kRejectController);
  EXPECT_EQ(p.counters().relocalization_applied, 1u);
}

TEST(MapUpdatePolicy, RejectsInvalidParameters) {
  EXPECT_THROW(MapUpdatePolicy({-1.0, 6}), std::invalid_argument);
  EXPECT_THROW(MapUpdatePolicy({0.3, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace edge_slam
