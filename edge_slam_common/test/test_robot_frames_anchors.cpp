// Each robot's frame stays attached to its anchor KeyFrame (RobotFrames::follow_anchors): when
// an optimisation moves a robot's whole map in the Global-Map (a loop between two robots' maps
// holds the other robot's KeyFrame fixed), T_group_robot follows, so the updates built for the
// robot keep its map where it is in its own frame, and the world stays robot 0's first map.
#include <gtest/gtest.h>

#include "edge_slam/module/robot_frames.h"
#include "edge_slam/util/robot_ids.h"
#include "support/yaw_pose.h"

namespace edge_slam {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw_deg) {
  return test_support::yaw_pose(x, y, z, yaw_deg * M_PI / 180.0);
}

bool near(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return a.isApprox(b, 1e-9); }

const uint32_t kRobot1First = keyframe_id_space(1).first;

TEST(RobotFramesAnchors, ARobotsFrameFollowsItsMapWhenTheMapIsMovedUnderIt) {
  RobotFrames frames(2);
  // Robot 1's map merged into robot 0's (world) 3 m away.
  const Eigen::Isometry3d T_0_1 = pose(3, 0, 0, 90);
  ASSERT_TRUE(frames.merge(1, 0, T_0_1));
  // KeyFrames in group 0's coordinates: robot 0's first at the origin, robot 1's first where
  // the merge put it (a KeyFrame at its robot's origin: T_cw = T_group_robot^-1).
  std::map<uint32_t, Eigen::Isometry3d> T_cw = {{0, Eigen::Isometry3d::Identity()}, {5, pose(0, 0, -1, 0)},
                                               {kRobot1First, T_0_1.inverse()}};
  frames.follow_anchors(T_cw);  // the anchors are taken
  ASSERT_TRUE(near(frames.placement(0).T_group_robot, Eigen::Isometry3d::Identity()));

  // A loop correction holding robot 1's KeyFrame moves robot 0's whole map by G (in group
  // coordinates: T_cw -> T_cw * G^-1), its first KeyFrame included.
  const Eigen::Isometry3d G = pose(0.1, 0, 0.02, 1);
  for (uint32_t id : {0u, 5u}) T_cw[id] = T_cw[id] * G.inverse();
  frames.follow_anchors(T_cw);
  // Robot 0's first KeyFrame is still at its origin in robot 0's frame, and so is the map
  // around it: an update brings robot 0 its map where it was.
  EXPECT_TRUE(near(T_cw[0] * frames.placement(0).T_group_robot, Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(near(T_cw[5] * frames.placement(0).T_group_robot, pose(0, 0, -1, 0)));
  // The world is robot 0's first map: TF world -> robot0/map stays identity ...
  ASSERT_TRUE(frames.placement(0).T_world_robot);
  EXPECT_TRUE(near(*frames.placement(0).T_world_robot, Eigen::Isometry3d::Identity()));
  // ... robot 1's map did not move in group coordinates while the world (robot 0's map) moved
  // by G in them: robot 1 is now at G^-1 * T_0_1 in the world,
  // and its own frame still has its first KeyFrame at its origin.
  EXPECT_TRUE(near(frames.placement(1).T_group_robot, T_0_1));
  ASSERT_TRUE(frames.placement(1).T_world_robot);
  EXPECT_TRUE(near(*frames.placement(1).T_world_robot, G.inverse() * T_0_1));
}

TEST(RobotFramesAnchors, AMergeMovesTheAnchorsWithTheirMap) {
  RobotFrames frames(2);
  std::map<uint32_t, Eigen::Isometry3d> T_cw = {{0, Eigen::Isometry3d::Identity()},
                                               {kRobot1First, Eigen::Isometry3d::Identity()}};
  frames.follow_anchors(T_cw);
  const Eigen::Isometry3d T_0_1 = pose(1, 2, 3, 30);
  ASSERT_TRUE(frames.merge(1, 0, T_0_1));
  T_cw[kRobot1First] = T_cw[kRobot1First] * T_0_1.inverse();  // as LoopClosing moves the group
  frames.follow_anchors(T_cw);
  EXPECT_TRUE(near(frames.placement(1).T_group_robot, T_0_1)) << "the move is the merge's, not counted twice";
}

TEST(RobotFramesAnchors, AnAnchorThatLeavesTheMapIsReplacedByTheOldestKeyFrameLeft) {
  RobotFrames frames(2);
  std::map<uint32_t, Eigen::Isometry3d> T_cw = {{kRobot1First, Eigen::Isometry3d::Identity()},
                                               {kRobot1First + 3, pose(0, 0, 1, 0)}};
  frames.follow_anchors(T_cw);
  T_cw.erase(kRobot1First);  // culled
  frames.follow_anchors(T_cw);  // the new anchor is taken where it is now: no move
  EXPECT_TRUE(near(frames.placement(1).T_group_robot, Eigen::Isometry3d::Identity()));
  T_cw[kRobot1First + 3] = pose(0, 0, 1, 0) * pose(0.05, 0, 0, 0).inverse();
  frames.follow_anchors(T_cw);
  EXPECT_TRUE(near(T_cw[kRobot1First + 3] * frames.placement(1).T_group_robot, pose(0, 0, 1, 0)));
}

}  // namespace
}  // namespace edge_slam
