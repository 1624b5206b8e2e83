#include <edge_slam/util/rejection_counter.h>
#include <gtest/gtest.h>

using edge_slam::RejectionCounter;

TEST(RejectionCounter, NumbersDoNotMakeANewReason) {
  EXPECT_EQ(RejectionCounter::reason_kind("obs_kp_index[3] = 17 >= keypoints 4"), "obs_kp_index[#] = # >= keypoints #");
  RejectionCounter c;
  EXPECT_EQ(c.add("KeyFrame 12: descriptors hold 33 bytes"), 1u);  // first of its kind: logged
  EXPECT_EQ(c.add("KeyFrame 99: descriptors hold 31 bytes"), 2u);
  EXPECT_EQ(c.add("KeyFrame version 7, expected 1"), 1u);
  EXPECT_EQ(c.total(), 3u);
  EXPECT_EQ(c.by_kind().size(), 2u);
}

TEST(RejectionCounter, KindsAreBounded) {
  RejectionCounter c;
  for (char a = 'a'; a <= 'z'; ++a)
    for (char b = 'a'; b <= 'e'; ++b) c.add(std::string("colour encoding '") + a + b + "'");
  EXPECT_EQ(c.total(), 26u * 5u);
  EXPECT_EQ(c.by_kind().size(), RejectionCounter::kMaxKinds + 1);
  EXPECT_EQ(c.by_kind().at(RejectionCounter::kOtherKinds), 26u * 5u - RejectionCounter::kMaxKinds);
}
