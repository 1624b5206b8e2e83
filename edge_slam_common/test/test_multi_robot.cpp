// One edge, several mobiles (issue #16), checked where each rule lives:
//   - ids: each robot's KeyFrames and points come from its own ranges, and a map holding
//     another robot's KeyFrames never moves its allocator into them;
//   - the edge refuses (and counts) a record carrying another robot's ids, map unchanged;
//   - where each robot's map is (RobotFrames): groups, merges composing transforms, the world
//     staying robot 0's first map, a reset starting a new map;
//   - two robots on overlapping stretches of the synthetic walk: the edge recognises the place
//     across them, merges robot 1's map into robot 0's with the transform between their first
//     camera poses (ground truth), and robot 1's updates stay in robot 1's own frame.
#include <gtest/gtest.h>

#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/robot_frames.h"
#include "edge_slam/util/robot_ids.h"
#include "edge_slam/util/wall_clock.h"
#include "support/split_fixture.h"

namespace edge_slam {
namespace {

using namespace split_fixture;

double rotation_deg(const Eigen::Isometry3d& T) { return Eigen::AngleAxisd(T.rotation()).angle() * 180.0 / M_PI; }

TEST(RobotIds, EachRobotHasItsOwnRangesAndRobotZeroKeepsTheOneRobotIds) {
  EXPECT_EQ(keyframe_id_space(0).first, 0u);
  EXPECT_EQ(mobile_point_id_space(0).first, kMobilePointIdFirst);
  for (int r = 0; r + 1 < kMaxRobots; ++r) {
    EXPECT_EQ(keyframe_id_space(r).end, keyframe_id_space(r + 1).first);
    EXPECT_EQ(mobile_point_id_space(r).end, mobile_point_id_space(r + 1).first);
    EXPECT_EQ(robot_of_keyframe(keyframe_id_space(r).first), r);
    EXPECT_EQ(robot_of_keyframe(keyframe_id_space(r).end - 1), r);
  }
  EXPECT_LE(mobile_point_id_space(kMaxRobots - 1).end, kEdgePointIdFirst) << "mobile points never reach the edge's";
  EXPECT_LT(keyframe_id_space(kMaxRobots - 1).end - 1, kNoId);
  EXPECT_FALSE(valid_robot_index(-1));
  EXPECT_FALSE(valid_robot_index(kMaxRobots));
}

TEST(RobotIds, AnotherRobotsKeyFrameDoesNotMoveTheAllocator) {
  Map map;
  const IdSpace mine = keyframe_id_space(0);
  map.set_keyframe_id_space(mine.first, mine.end);
  const auto features = std::make_shared<FrameFeatures>();
  map.add_keyframe(std::make_shared<KeyFrame>(5, 0, 0.0, features, Eigen::Isometry3d::Identity()));
  map.add_keyframe(std::make_shared<KeyFrame>(keyframe_id_space(1).first + 7, 0, 0.0, features,
                                              Eigen::Isometry3d::Identity()));
  EXPECT_EQ(map.new_keyframe_id(), 6u) << "past its own, not past robot 1's";
}

TEST(RobotFramesTest, MergesComposeAndTheWorldStaysRobotZerosFirstMap) {
  RobotFrames frames(3);
  EXPECT_EQ(frames.group_of(keyframe_id_space(0).first + 3), 0);
  EXPECT_EQ(frames.group_of(keyframe_id_space(2).first), 2);
  EXPECT_EQ(frames.group_of(keyframe_id_space(5).first), -1) << "not a configured robot";
  ASSERT_TRUE(frames.placement(0).T_world_robot);
  EXPECT_FALSE(frames.placement(1).T_world_robot) << "unplaced before any merge";

  Eigen::Isometry3d T21 = Eigen::Isometry3d::Identity();  // robot 1's map into robot 2's
  T21.translate(Eigen::Vector3d(1, 0, 0));
  ASSERT_TRUE(frames.merge(1, 2, T21));
  EXPECT_EQ(frames.placement(1).group, 2);
  EXPECT_FALSE(frames.placement(1).T_world_robot) << "neither map is robot 0's yet";
  EXPECT_FALSE(frames.merge(1, 2, T21)) << "group 1 is gone";

  Eigen::Isometry3d T02 = Eigen::Isometry3d::Identity();  // then robot 2's (with 1's) into robot 0's
  T02.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  T02.translate(Eigen::Vector3d(0, 2, 0));
  ASSERT_TRUE(frames.merge(2, 0, T02));
  for (int r = 0; r < 3; ++r) EXPECT_EQ(frames.placement(r).group, 0);
  ASSERT_TRUE(frames.placement(1).T_world_robot);
  EXPECT_TRUE(frames.placement(1).T_world_robot->isApprox(T02 * T21));
  EXPECT_TRUE(frames.placement(2).T_world_robot->isApprox(T02));
  EXPECT_TRUE(frames.placement(0).T_world_robot->isApprox(Eigen::Isometry3d::Identity()));
}

TEST(RobotFramesTest, TheHostMovedIntoAnUnplacedGroupKeepsTheWorld) {
  RobotFrames frames(2);
  Eigen::Isometry3d T10 = Eigen::Isometry3d::Identity();  // robot 0's map moved into robot 1's
  T10.translate(Eigen::Vector3d(0, 0, 3));
  ASSERT_TRUE(frames.merge(0, 1, T10));
  ASSERT_TRUE(frames.placement(0).T_world_robot);
  EXPECT_TRUE(frames.placement(0).T_world_robot->isApprox(Eigen::Isometry3d::Identity()))
      << "world = robot 0's first map, wherever it is stored";
  EXPECT_TRUE(frames.placement(1).T_world_robot->isApprox(T10.inverse()));
}

TEST(RobotFramesTest, AResetStartsANewMapAndTheOldKeyFramesKeepTheirs) {
  RobotFrames frames(2);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(1, 2, 3));
  ASSERT_TRUE(frames.merge(1, 0, T));
  const uint32_t first = keyframe_id_space(1).first;
  frames.start_new_map(1, first + 10);
  EXPECT_EQ(frames.group_of(first + 9), 0) << "made before the reset: still in robot 0's map";
  EXPECT_NE(frames.group_of(first + 10), 0);
  EXPECT_FALSE(frames.placement(1).T_world_robot) << "the new map is nowhere yet";
  EXPECT_TRUE(frames.placement(1).T_group_robot.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(RobotFramesTest, RecordsMoveWithTheirPoints) {
  KeyFrameRecord k;
  k.T_wc.translation() = Eigen::Vector3d(1, 0, 0);
  NewPointRecord p;
  p.position = Eigen::Vector3f(0, 1, 0);
  k.new_points.push_back(p);
  MapUpdateRecord u;
  u.keyframes.push_back(k);
  MapPointRecord mp;
  mp.position = Eigen::Vector3f(0, 0, 1);
  mp.normal = Eigen::Vector3f(1, 0, 0);
  u.points.push_back(mp);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  T.pretranslate(Eigen::Vector3d(0, 0, 5));
  transform_update(u, T);
  EXPECT_TRUE(u.keyframes[0].T_wc.translation().isApprox(Eigen::Vector3d(0, 1, 5)));
  EXPECT_TRUE(u.keyframes[0].new_points[0].position.isApprox(Eigen::Vector3f(-1, 0, 5), 1e-5f));
  EXPECT_TRUE(u.points[0].position.isApprox(Eigen::Vector3f(0, 0, 6), 1e-5f));
  EXPECT_TRUE(u.points[0].normal.isApprox(Eigen::Vector3f(0, 1, 0), 1e-5f)) << "a direction: rotated only";
}

// A mobile's condition 2 with an edge that maps this robot's KeyFrames at once but, when
// `busy_elsewhere`, says its Local-Mapping holds another robot's KeyFrame.
int keyframes_made_with(bool busy_elsewhere) {
  const RenderedSequence& seq = sequence();
  MobileSession session = make_session();
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
    session.on_edge_progress(session.keyframes_sent(), busy_elsewhere);
  }
  return static_cast<int>(session.keyframes_sent());
}

TEST(MultiRobotPacing, AMapperBusyWithAnotherRobotHoldsKeyFramesBackAsIfBusyWithOurs) {
  const int idle = keyframes_made_with(false), busy = keyframes_made_with(true);
  EXPECT_LT(busy, idle) << "condition 2 reads the shared Local-Mapping";
  EXPECT_LE(busy, 1 + kFrames / 20 + 1) << "a KeyFrame every 20 frames (or on weak tracking), as with a busy mapper";
}

TEST(MultiRobotEdge, ARecordWithAnotherRobotsIdsIsRefusedAndCounted) {
  const RenderedSequence& seq = sequence();
  const std::vector<KeyFrameRecord> robot1 = robot_keyframes(1, 0, 12);
  ASSERT_GE(robot1.size(), 2u);
  for (const KeyFrameRecord& r : robot1) {
    EXPECT_TRUE(keyframe_id_space(1).contains(r.id));
    for (const NewPointRecord& p : r.new_points) EXPECT_TRUE(mobile_point_id_space(1).contains(p.id));
  }
  EdgeSessionParams params;
  params.robots = 2;
  params.loop_closing = false;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  std::string error;
  EXPECT_EQ(edge.receive_keyframe(robot1[0], wall_clock_seconds(), &error, 0), KeyFrameVerdict::kInvalid);
  EXPECT_NE(error.find("not robot 0's"), std::string::npos) << error;
  KeyFrameRecord foreign_point = robot1[0];
  foreign_point.id = keyframe_id_space(0).first + 1;  // robot 0's KeyFrame id, robot 1's points
  EXPECT_EQ(edge.receive_keyframe(foreign_point, wall_clock_seconds(), &error, 0), KeyFrameVerdict::kInvalid);
  EXPECT_NE(error.find("new map point id"), std::string::npos) << error;
  EXPECT_EQ(edge.receive_keyframe(robot1[0], wall_clock_seconds(), &error, 5), KeyFrameVerdict::kInvalid);
  EXPECT_EQ(edge.counters(0).foreign_ids, 2u);
  EXPECT_EQ(edge.counters(0).invalid, 2u);
  EXPECT_EQ(edge.global_map()->num_keyframes(), 0u) << "nothing of them in the map";
  EXPECT_EQ(edge.global_map()->num_map_points(), 0u);
  EXPECT_EQ(edge.receive_keyframe(robot1[0], wall_clock_seconds(), &error, 1), KeyFrameVerdict::kInserted) << error;
  EXPECT_EQ(edge.counters(1).inserted, 1u);
  EXPECT_EQ(edge.counters(0).inserted, 0u) << "counted for the robot that sent it";
  ASSERT_TRUE(edge.wait_until_idle(30.0));
}

TEST(MultiRobotEdge, AResetClearsOnlyTheResettingRobotsState) {
  const RenderedSequence& seq = sequence();
  const std::vector<KeyFrameRecord> robot0 = robot_keyframes(0, 0, 10), robot1 = robot_keyframes(1, 0, 10);
  ASSERT_GE(robot1.size(), 2u);
  EdgeSessionParams params;
  params.robots = 2;
  params.loop_closing = false;
  params.late_keyframe_age = 0;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(edge.receive_keyframe(robot0[i], wall_clock_seconds(), nullptr, 0), KeyFrameVerdict::kInserted);
    ASSERT_TRUE(edge.wait_until_idle(30.0));
    ASSERT_EQ(edge.receive_keyframe(robot1[i], wall_clock_seconds(), nullptr, 1), KeyFrameVerdict::kInserted);
    ASSERT_TRUE(edge.wait_until_idle(30.0));
  }
  const size_t keyframes = edge.global_map()->num_keyframes();
  const int group_before = edge.frames().group_of(robot1[1].id);
  KeyFrameRecord reset = robot1[1];
  reset.reset = true;
  reset.seq = robot1.back().seq + 1;
  EXPECT_EQ(edge.receive_keyframe(reset, wall_clock_seconds(), nullptr, 1), KeyFrameVerdict::kReset);
  EXPECT_EQ(edge.counters(1).resets, 1u);
  EXPECT_EQ(edge.counters(0).resets, 0u);
  EXPECT_EQ(edge.global_map()->num_keyframes(), keyframes) << "robot 1's old KeyFrames stay for the others";
  EXPECT_TRUE(edge.keyframe_account(1).inserted.empty()) << "robot 1's accounting starts again";
  EXPECT_EQ(edge.keyframe_account(0).inserted.size(), 2u) << "robot 0 is untouched";
  EXPECT_EQ(edge.frames().group_of(robot1[1].id), group_before);
  EXPECT_NE(edge.frames().group_of(reset.id + 1), group_before) << "its next KeyFrames start a map of their own";
  EXPECT_FALSE(edge.placement(1).T_world_robot);
  ASSERT_TRUE(edge.placement(0).T_world_robot);
}

TEST(MultiRobotEdge, OverlappingWalksAreMergedWithTheTransformBetweenTheirFirstPoses) {
  const RenderedSequence& seq = sequence();
  const int offset = 20;  // robot 1 starts where robot 0 was 1.3 s in
  const std::vector<KeyFrameRecord> robot0 = robot_keyframes(0, 0, kFrames);
  const std::vector<KeyFrameRecord> robot1 = robot_keyframes(1, offset, kFrames);
  ASSERT_GE(robot1.size(), 6u);
  EdgeSessionParams params;
  params.robots = 2;
  params.late_keyframe_age = 0;
  params.loop.full_ba_in_background = false;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (const KeyFrameRecord& r : robot0) {
    edge.receive_keyframe(r, wall_clock_seconds(), nullptr, 0);
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
  EXPECT_TRUE(edge.merges().empty()) << "one robot: nothing to merge";
  EXPECT_FALSE(edge.placement(1).T_world_robot);
  for (const KeyFrameRecord& r : robot1) {
    edge.receive_keyframe(r, wall_clock_seconds(), nullptr, 1);
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
  ASSERT_EQ(edge.merges().size(), 1u) << "robot 1 walks where robot 0 walked";
  EXPECT_EQ(robot_of_keyframe(edge.merges()[0].current_kf_id), 1);
  EXPECT_EQ(robot_of_keyframe(edge.merges()[0].loop_kf_id), 0);
  const std::optional<Eigen::Isometry3d> T_world_1 = edge.placement(1).T_world_robot;
  ASSERT_TRUE(T_world_1);
  // Each mobile's map starts at its first camera pose, so robot 1's map sits in robot 0's where
  // the camera of frame `offset` was seen from that of frame 0.
  const Trajectory trajectory(42);
  const Eigen::Isometry3d truth = trajectory.pose_at(0.0).inverse() * trajectory.pose_at(offset / 15.0);
  const Eigen::Isometry3d error = truth.inverse() * *T_world_1;
  EXPECT_LT(error.translation().norm(), 0.03) << "m";
  EXPECT_LT(rotation_deg(error), 1.0);
  EXPECT_TRUE(edge.mapping_idle());

  // Robot 1's updates are in robot 1's own frame: its KeyFrames come back where it put them.
  const std::optional<MapUpdateRecord> u = edge.build_local_map_update(1.0, 1);
  ASSERT_TRUE(u);
  int own = 0;
  for (const KeyFrameRecord& k : u->keyframes) {
    const auto sent = std::find_if(robot1.begin(), robot1.end(), [&](const KeyFrameRecord& r) { return r.id == k.id; });
    if (sent == robot1.end()) continue;
    ++own;
    EXPECT_LT((sent->T_wc.translation() - k.T_wc.translation()).norm(), 0.03) << "KeyFrame " << k.id;
  }
  EXPECT_GT(own, 0);
}

TEST(MultiRobotEdge, WhenRobotZeroFindsTheOtherMapTheWorldStaysPut) {
  // Robot 1 maps first; robot 0's KeyFrames then find robot 1's: the loop side (group 1) moves
  // into robot 0's coordinates, never the other way (group 0 is the world).
  const RenderedSequence& seq = sequence();
  const int offset = 20;
  const std::vector<KeyFrameRecord> robot1 = robot_keyframes(1, offset, kFrames);
  const std::vector<KeyFrameRecord> robot0 = robot_keyframes(0, 0, kFrames);
  EdgeSessionParams params;
  params.robots = 2;
  params.late_keyframe_age = 0;
  params.loop.full_ba_in_background = false;
  params.loop.full_ba = false;  // the stored poses of robot 0 are compared with what it sent
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (const KeyFrameRecord& r : robot1) {
    edge.receive_keyframe(r, wall_clock_seconds(), nullptr, 1);
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
  for (const KeyFrameRecord& r : robot0) {
    edge.receive_keyframe(r, wall_clock_seconds(), nullptr, 0);
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
  ASSERT_EQ(edge.merges().size(), 1u);
  EXPECT_EQ(robot_of_keyframe(edge.merges()[0].current_kf_id), 0);
  EXPECT_EQ(edge.merges()[0].group_into, 0);
  const Trajectory trajectory(42);
  const Eigen::Isometry3d truth = trajectory.pose_at(0.0).inverse() * trajectory.pose_at(offset / 15.0);
  ASSERT_TRUE(edge.placement(1).T_world_robot);
  const Eigen::Isometry3d error = truth.inverse() * *edge.placement(1).T_world_robot;
  EXPECT_LT(error.translation().norm(), 0.03) << "m";
  EXPECT_LT(rotation_deg(error), 1.0);
  const auto first = edge.global_map()->keyframe(robot0.front().id);
  ASSERT_TRUE(first);
  EXPECT_LT(first->T_wc().translation().norm(), 0.01) << "robot 0's first KeyFrame is still the world's origin";
}

}  // namespace
}  // namespace edge_slam
