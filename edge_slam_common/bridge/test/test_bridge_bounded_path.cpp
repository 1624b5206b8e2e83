// BoundedPath: ~path holds the newest poses only, in order, is published on every `every`-th
// pose, and its storage is reserved once and never grows however long the robot runs.
#include <gtest/gtest.h>

#include <vector>

#include "edge_slam_bridge/bounded_path.h"

namespace edge_slam {
namespace {

geometry_msgs::PoseStamped pose(uint32_t seq) {
  geometry_msgs::PoseStamped p;
  p.header.seq = seq;
  p.header.frame_id = "map";
  p.pose.position.x = seq;
  p.pose.orientation.w = 1.0;
  return p;
}

TEST(BoundedPath, KeepsTheNewestPosesPublishesEveryNthAndNeverGrowsItsStorage) {
  BoundedPath path(4, 3);
  const size_t reserved = path.capacity();
  EXPECT_GE(reserved, 5u);
  std::vector<nav_msgs::Path> published;
  for (uint32_t i = 1; i <= 1000; ++i) {
    path.add(pose(i), [&](const nav_msgs::Path& p) { published.push_back(p); });
    EXPECT_EQ(path.capacity(), reserved) << "pose " << i;
  }
  ASSERT_EQ(published.size(), 333u) << "every 3rd pose";
  const nav_msgs::Path& last = published.back();  // made at pose 999
  ASSERT_EQ(last.poses.size(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(last.poses[k].header.seq, 996 + k) << "oldest first";
  EXPECT_EQ(last.header.seq, 999u) << "the header of the newest pose";
  EXPECT_EQ(published.front().poses.size(), 3u) << "fewer poses than the bound: all of them";
}

TEST(BoundedPath, ClearKeepsTheReservationAndALowerBoundDropsTheOldest) {
  BoundedPath path(10, 1);
  std::vector<nav_msgs::Path> published;
  const auto keep = [&](const nav_msgs::Path& p) { published.push_back(p); };
  for (uint32_t i = 1; i <= 8; ++i) path.add(pose(i), keep);
  path.set_max_poses(3);
  path.add(pose(9), keep);
  ASSERT_EQ(published.back().poses.size(), 3u);
  EXPECT_EQ(published.back().poses.front().header.seq, 7u);
  const size_t reserved = path.capacity();
  path.clear();
  EXPECT_EQ(path.capacity(), reserved);
  path.add(pose(10), keep);
  ASSERT_EQ(published.back().poses.size(), 1u);
  EXPECT_EQ(published.back().poses.front().header.seq, 10u);
}

}  // namespace
}  // namespace edge_slam
