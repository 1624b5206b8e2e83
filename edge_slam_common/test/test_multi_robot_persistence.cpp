// Persistence with several mobiles (issue #16): a checkpoint holds every robot's map, its
// deliveries and where its maps are (merges included), and a restarted edge resumes them all.
//   - save / load round trip on two robots whose maps merged: same Global-Map, same placement of
//     robot 1 in the world, same accounting and received seq per robot; a resent KeyFrame is a
//     duplicate for its own robot; robot 1's updates still come in robot 1's frame;
//   - the loop detector's history (each robot's pause after the merge, its candidate groups)
//     survives the restart: a restored edge saves the same history again;
//   - a restored edge announces the file's merges once more, marked restored (EdgeSystem):
//     its latched ~merges starts empty otherwise, and its CSV must not count them as new;
//   - a file of another number of robots is refused and the map kept;
//   - EdgeDurability: a checkpoint makes each robot's own seqs durable; a restore acknowledges
//     each robot its own durable seq under a new boot id.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>

#include "edge_slam/io/map_file.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/split/edge_durability.h"
#include "edge_slam/split/edge_system.h"
#include "edge_slam/util/robot_ids.h"
#include "edge_slam/util/wall_clock.h"
#include "support/csv_rows.h"
#include "support/split_fixture.h"

namespace edge_slam {
namespace {

using namespace split_fixture;

std::string temp_path(const char* name) {
  return "/tmp/edge_slam_multi_persistence_" + std::to_string(::getpid()) + "_" + name;
}

EdgeSessionParams two_robots() {
  EdgeSessionParams params;
  params.robots = 2;
  params.late_keyframe_age = 0;
  params.loop.full_ba_in_background = false;
  return params;
}

// Two robots on overlapping stretches of the walk (robot 1 from frame 20), robot 0 first: the
// edge merges robot 1's map into robot 0's (as test_multi_robot checks in detail).
struct MergedWalks {
  std::vector<KeyFrameRecord> robot0 = robot_keyframes(0, 0, kFrames), robot1 = robot_keyframes(1, 20, kFrames);
};

const MergedWalks& walks() {
  static const MergedWalks w;
  return w;
}

void feed(EdgeSession& edge, const std::vector<KeyFrameRecord>& records, int robot, size_t count) {
  for (size_t i = 0; i < count && i < records.size(); ++i) {
    edge.receive_keyframe(records[i], wall_clock_seconds(), nullptr, robot);
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
}

EdgeSession make_edge(int robots = 2) {
  EdgeSessionParams params = two_robots();
  params.robots = robots;
  return EdgeSession(sequence().camera, 8, 1.2f, sequence().vocabulary, params);
}

double distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return (a.inverse() * b).translation().norm(); }

TEST(MultiRobotPersistence, ARestoredEdgeHasEveryRobotsMapDeliveriesAndPlacement) {
  const MergedWalks& w = walks();
  ASSERT_GE(w.robot1.size(), 6u);
  EdgeSession before = make_edge();
  feed(before, w.robot0, 0, w.robot0.size());
  const size_t robot1_saved = w.robot1.size() - 2;  // the last two come after the save
  feed(before, w.robot1, 1, robot1_saved);
  ASSERT_EQ(before.merges().size(), 1u) << "the walks overlap";
  ASSERT_TRUE(before.placement(1).T_world_robot);
  const std::string file = temp_path("merged.esmap");
  const std::vector<uint64_t> durable = before.save_map(file);
  ASSERT_EQ(durable.size(), 2u);
  EXPECT_EQ(durable[0], before.counters(0).received_seq);
  EXPECT_EQ(durable[1], before.counters(1).received_seq);
  EXPECT_GT(durable[1], 0u);

  const MapSnapshot saved = read_map_file(file);
  // The merge was a loop for the detector: each robot waits for min_keyframes_after_loop more.
  ASSERT_EQ(saved.loop_robots.size(), 2u);
  for (const LoopRobotRecord& r : saved.loop_robots) EXPECT_TRUE(r.last_loop_keyframe) << "robot " << r.robot;

  EdgeSession after = make_edge();
  after.load_map(file);
  std::remove(file.c_str());
  {  // Saved again at once, the restored edge writes the same detector history.
    const std::string again = temp_path("merged_again.esmap");
    after.save_map(again);
    const MapSnapshot resaved = read_map_file(again);
    std::remove(again.c_str());
    ASSERT_EQ(resaved.loop_robots.size(), saved.loop_robots.size());
    for (size_t i = 0; i < saved.loop_robots.size(); ++i) {
      EXPECT_EQ(resaved.loop_robots[i].robot, saved.loop_robots[i].robot);
      EXPECT_EQ(resaved.loop_robots[i].newest_keyframe, saved.loop_robots[i].newest_keyframe);
      EXPECT_EQ(resaved.loop_robots[i].last_loop_keyframe, saved.loop_robots[i].last_loop_keyframe);
    }
    ASSERT_EQ(resaved.loop_groups.size(), saved.loop_groups.size());
    for (size_t i = 0; i < saved.loop_groups.size(); ++i) {
      EXPECT_EQ(resaved.loop_groups[i].robot, saved.loop_groups[i].robot);
      EXPECT_EQ(resaved.loop_groups[i].consistency, saved.loop_groups[i].consistency);
      EXPECT_EQ(resaved.loop_groups[i].members, saved.loop_groups[i].members);
    }
  }
  EXPECT_EQ(after.global_map()->num_keyframes(), before.global_map()->num_keyframes());
  EXPECT_EQ(after.global_map()->num_map_points(), before.global_map()->num_map_points());
  for (int r = 0; r < 2; ++r) {
    EXPECT_EQ(after.counters(r).received_seq, before.counters(r).received_seq) << "robot " << r;
    EXPECT_EQ(after.keyframe_account(r).inserted, before.keyframe_account(r).inserted) << "robot " << r;
    EXPECT_EQ(after.keyframe_account(r).in_map, before.keyframe_account(r).in_map) << "robot " << r;
    EXPECT_EQ(after.placement(r).group, before.placement(r).group) << "robot " << r;
  }
  ASSERT_TRUE(after.placement(1).T_world_robot) << "the merge survives the restart";
  EXPECT_LT(distance(*after.placement(1).T_world_robot, *before.placement(1).T_world_robot), 1e-9);
  EXPECT_EQ(after.frames().group_of(w.robot1.front().id), after.frames().group_of(w.robot0.front().id));
  // The merge history too: a restarted edge still reports the merge made before it.
  ASSERT_EQ(after.merges().size(), 1u);
  EXPECT_EQ(after.merges()[0].current_kf_id, before.merges()[0].current_kf_id);
  EXPECT_EQ(after.merges()[0].loop_kf_id, before.merges()[0].loop_kf_id);
  EXPECT_EQ(after.merges()[0].matches, before.merges()[0].matches);
  EXPECT_LT(distance(after.merges()[0].T_into_from, before.merges()[0].T_into_from), 1e-9);

  // A KeyFrame robot 1 sent before the save comes again (the mobile resends what was not
  // durable): a duplicate, counted for robot 1; the next new ones go in.
  EXPECT_EQ(after.receive_keyframe(w.robot1[robot1_saved - 1], wall_clock_seconds(), nullptr, 1),
            KeyFrameVerdict::kDuplicate);
  EXPECT_EQ(after.counters(1).duplicates, 1u);
  EXPECT_EQ(after.counters(0).duplicates, 0u);
  for (size_t i = robot1_saved; i < w.robot1.size(); ++i) {
    EXPECT_EQ(after.receive_keyframe(w.robot1[i], wall_clock_seconds(), nullptr, 1), KeyFrameVerdict::kInserted) << i;
    ASSERT_TRUE(after.wait_until_idle(60.0));
  }
  // Robot 1's update is in its own frame: its KeyFrames come back where it put them.
  const std::optional<MapUpdateRecord> u = after.build_local_map_update(1.0, 1);
  ASSERT_TRUE(u);
  int own = 0;
  for (const KeyFrameRecord& k : u->keyframes) {
    const auto sent = std::find_if(w.robot1.begin(), w.robot1.end(), [&](const KeyFrameRecord& r) { return r.id == k.id; });
    if (sent == w.robot1.end()) continue;
    ++own;
    EXPECT_LT((sent->T_wc.translation() - k.T_wc.translation()).norm(), 0.03) << "KeyFrame " << k.id;
  }
  EXPECT_GT(own, 0);
}

TEST(MultiRobotPersistence, ARestoredEdgeAnnouncesTheFilesMergesOnceAsRestored) {
  const MergedWalks& w = walks();
  const std::string file = temp_path("announced.esmap");
  {
    EdgeSession before = make_edge();
    feed(before, w.robot0, 0, w.robot0.size());
    feed(before, w.robot1, 1, w.robot1.size());
    ASSERT_EQ(before.merges().size(), 1u) << "the walks overlap";
    before.save_map(file);
  }
  EdgeSystemSettings s;
  s.camera = sequence().camera;
  s.session = two_robots();
  s.vocabulary = sequence().vocabulary;
  s.restore_on_start = false;
  s.files.events = temp_path("announced_events.csv");
  {
    EdgeSystem edge(s);
    std::string message;
    ASSERT_TRUE(edge.load_map(file, &message)) << message;
    const std::vector<MergeEvent> told = edge.new_merges(1.0);
    ASSERT_EQ(told.size(), 1u) << "the restored merge goes out on ~merges";
    EXPECT_EQ(told[0].current_kf_id, edge.session().merges()[0].current_kf_id);
    EXPECT_TRUE(edge.new_merges(2.0).empty()) << "once";
    edge.write_outputs();
  }
  int restored = 0, merged = 0;
  for (const auto& row : test_support::read_csv_rows(s.files.events)) {
    restored += row.at("event") == "merge_restored";
    merged += row.at("event") == "merge";
  }
  EXPECT_EQ(restored, 1);
  EXPECT_EQ(merged, 0) << "a merge of an earlier run is not one of this run";
  std::remove(file.c_str());
  std::remove(s.files.events.c_str());
}

TEST(MultiRobotPersistence, AFileOfAnotherNumberOfRobotsIsRefusedAndTheMapKept) {
  const MergedWalks& w = walks();
  EdgeSession two = make_edge(2);
  feed(two, w.robot0, 0, 3);
  const std::string file2 = temp_path("two.esmap");
  two.save_map(file2);
  EdgeSession one = make_edge(1);
  feed(one, w.robot0, 0, 2);
  const std::string file1 = temp_path("one.esmap");
  one.save_map(file1);

  try {
    one.load_map(file2);
    ADD_FAILURE() << "a one-robot edge loaded a two-robot file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("2 robot(s); this edge serves 1"), std::string::npos) << e.what();
  }
  EXPECT_EQ(one.global_map()->num_keyframes(), 2u) << "the map is kept";
  EXPECT_THROW(two.load_map(file1), std::runtime_error);
  EXPECT_EQ(two.global_map()->num_keyframes(), 3u);
  std::remove(file1.c_str());
  std::remove(file2.c_str());
}

TEST(MultiRobotPersistence, EachRobotIsAcknowledgedItsOwnDurableSeqAfterARestore) {
  const MergedWalks& w = walks();
  const std::string file = temp_path("checkpoint.esmap");
  uint64_t boot = 0;
  const auto boot_ids = [&boot] { return ++boot; };
  uint64_t seq0 = 0, seq1 = 0;
  {
    EdgeSession edge = make_edge();
    EdgeDurability durability(edge, DurabilityParams{file, 5.0}, boot_ids);
    feed(edge, w.robot0, 0, 4);
    feed(edge, w.robot1, 1, 2);
    seq0 = edge.counters(0).received_seq;
    seq1 = edge.counters(1).received_seq;
    ASSERT_NE(seq0, seq1) << "the robots' seqs differ: the test tells them apart";
    EXPECT_EQ(durability.ack(1).durable_seq, 0u) << "nothing durable before a checkpoint";
    ASSERT_TRUE(durability.checkpoint("test", 0.0));
    EXPECT_EQ(durability.ack(0).durable_seq, seq0);
    EXPECT_EQ(durability.ack(1).durable_seq, seq1);
  }
  EdgeSession restarted = make_edge();
  EdgeDurability durability(restarted, DurabilityParams{file, 5.0}, boot_ids);
  ASSERT_EQ(durability.restore(0.0), RestoreResult::kRestored);
  const KeyFrameAck a0 = durability.ack(0), a1 = durability.ack(1);
  EXPECT_EQ(a0.boot_id, 2u) << "a new boot: both mobiles resend what is not durable";
  EXPECT_EQ(a1.boot_id, 2u);
  EXPECT_EQ(a0.durable_seq, seq0);
  EXPECT_EQ(a1.durable_seq, seq1);
  EXPECT_EQ(a1.received_seq, seq1);
  EXPECT_EQ(restarted.global_map()->num_keyframes(), 6u);
  std::remove(file.c_str());
}

}  // namespace
}  // namespace edge_slam
