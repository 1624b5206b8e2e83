#include <gtest/gtest.h>

#include "edge_slam/module/keyframe_decision.h"

using namespace edge_slam;

namespace {
KeyFrameDecisionInput wants_keyframe() {
  KeyFrameDecisionInput in;
  in.frame_id = 100;
  in.last_keyframe_frame_id = 90;
  in.mapper_idle = true;
  in.tracked_points = 200;
  in.reference_tracked_points = 300;  // 200 < 0.9 * 300
  in.tracked_close_points = 150;
  in.untracked_close_points = 10;
  return in;
}
}  // namespace

TEST(KeyFrameDecision, Condition1RelocalizationGap) {
  KeyFrameDecisionParams p;
  KeyFrameDecisionInput in = wants_keyframe();
  EXPECT_TRUE(relocalization_gap_passed(p, in));  // never relocalized
  in.relocalized_before = true;
  in.last_relocalization_frame_id = 85;
  EXPECT_FALSE(relocalization_gap_passed(p, in));  // 15 frames
  in.last_relocalization_frame_id = 80;
  EXPECT_TRUE(relocalization_gap_passed(p, in));  // 20 frames
}

TEST(KeyFrameDecision, Condition2FramesOrMapperIdle) {
  KeyFrameDecisionParams p;
  KeyFrameDecisionInput in = wants_keyframe();
  EXPECT_TRUE(keyframe_gap_or_mapper_idle(p, in));
  in.mapper_idle = false;
  EXPECT_FALSE(keyframe_gap_or_mapper_idle(p, in));  // 10 frames, mapper busy
  in.last_keyframe_frame_id = 80;
  EXPECT_TRUE(keyframe_gap_or_mapper_idle(p, in));  // 20 frames
  // Weak tracking overrides a busy mapper (ORB-SLAM2 RGB-D c1c).
  in.last_keyframe_frame_id = 90;
  in.tracked_points = 70;  // < 0.25 * 300
  EXPECT_TRUE(keyframe_gap_or_mapper_idle(p, in));
  in.tracked_points = 200;
  in.tracked_close_points = 40;
  in.untracked_close_points = 200;  // close points needed
  EXPECT_TRUE(keyframe_gap_or_mapper_idle(p, in));
}

TEST(KeyFrameDecision, Condition3EnoughTrackedPoints) {
  KeyFrameDecisionParams p;
  KeyFrameDecisionInput in = wants_keyframe();
  in.tracked_points = 49;
  EXPECT_FALSE(tracks_enough_points(p, in));
  in.tracked_points = 50;
  EXPECT_TRUE(tracks_enough_points(p, in));
  // The last frame's depth points support the pose as well (tracking/last_frame_depth_points).
  in.tracked_points = 20;
  in.depth_point_inliers = 29;
  EXPECT_FALSE(tracks_enough_points(p, in));
  in.depth_point_inliers = 30;
  EXPECT_TRUE(tracks_enough_points(p, in));
}

TEST(KeyFrameDecision, Condition4FewerThanReference) {
  KeyFrameDecisionParams p;
  KeyFrameDecisionInput in = wants_keyframe();
  in.reference_tracked_points = 200;
  in.tracked_points = 180;
  EXPECT_FALSE(tracks_fewer_than_reference(p, in));  // exactly 90%
  in.tracked_points = 179;
  EXPECT_TRUE(tracks_fewer_than_reference(p, in));
  p.ref_ratio = 0.75;
  EXPECT_FALSE(tracks_fewer_than_reference(p, in));
}

TEST(KeyFrameDecision, Condition5ClosePoints) {
  KeyFrameDecisionParams p;
  KeyFrameDecisionInput in = wants_keyframe();
  in.tracked_close_points = 99;
  in.untracked_close_points = 71;
  EXPECT_TRUE(needs_close_points(p, in));
  in.untracked_close_points = 70;
  EXPECT_FALSE(needs_close_points(p, in));
  in.untracked_close_points = 71;
  in.tracked_close_points = 100;
  EXPECT_FALSE(needs_close_points(p, in));
}

TEST(KeyFrameDecision, ConditionSetsSplitBetweenEdgeAndMobile) {
  KeyFrameDecisionParams p;
  KeyFrameDecisionInput in = wants_keyframe();
  EXPECT_TRUE(need_new_keyframe(p, in, KeyFrameConditionSet::kAll));
  // Mapper busy and few frames: the edge would refuse, the mobile still proposes.
  in.mapper_idle = false;
  EXPECT_FALSE(need_new_keyframe(p, in, KeyFrameConditionSet::kAll));
  EXPECT_FALSE(need_new_keyframe(p, in, KeyFrameConditionSet::kEdge));
  EXPECT_TRUE(need_new_keyframe(p, in, KeyFrameConditionSet::kMobile));
  // Tracking as well as the reference, no close-point need: no keyframe anywhere but edge.
  in = wants_keyframe();
  in.reference_tracked_points = 210;
  EXPECT_FALSE(need_new_keyframe(p, in, KeyFrameConditionSet::kMobile));
  EXPECT_TRUE(need_new_keyframe(p, in, KeyFrameConditionSet::kEdge));
  EXPECT_FALSE(need_new_keyframe(p, in, KeyFrameConditionSet::kAll));
  // ... unless close points are needed (5 is an alternative to 4).
  in.tracked_close_points = 40;
  in.untracked_close_points = 200;
  EXPECT_TRUE(need_new_keyframe(p, in, KeyFrameConditionSet::kAll));
}
