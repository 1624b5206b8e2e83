// EdgeSession::save_map / load_map: a restarted edge continues the same Global-Map (same
// KeyFrames, points, graph and database; resent KeyFrames are duplicates), saving works
// while Local-Mapping runs, and a corrupt file leaves the running map alone.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <thread>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/util/wall_clock.h"
#include "support/sent_keyframes.h"

namespace edge_slam {
namespace {

using Mobile = test_support::SentKeyFrames;

std::string temp_path(const char* name) {
  return "/tmp/edge_slam_test_" + std::to_string(::getpid()) + "_" + name;
}

void feed(EdgeSession& edge, const Mobile& mobile) {
  for (const KeyFrameRecord& r : mobile.sent) {
    std::string error;
    EXPECT_EQ(edge.receive_keyframe(r, wall_clock_seconds(), &error), KeyFrameVerdict::kInserted) << error;
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
}

TEST(EdgePersistence, RestartedEdgeContinuesTheSameMap) {
  const Mobile mobile;
  const std::string path = temp_path("edge.esmap");
  EdgeSession edge(mobile.source.camera, 8, 1.2f, mobile.vocabulary, mobile.params());
  feed(edge, mobile);
  edge.save_map(path);
  const auto before = edge.global_map();

  EdgeSession restarted(mobile.source.camera, 8, 1.2f, mobile.vocabulary, mobile.params());
  restarted.load_map(path);
  std::remove(path.c_str());
  const auto after = restarted.global_map();
  ASSERT_GT(before->num_keyframes(), 0u);
  ASSERT_EQ(after->num_keyframes(), before->num_keyframes());
  ASSERT_EQ(after->num_map_points(), before->num_map_points());
  for (const auto& kf : before->keyframes()) {
    const auto other = after->keyframe(kf->id());
    ASSERT_TRUE(other);
    EXPECT_TRUE(other->T_cw().isApprox(kf->T_cw(), 1e-12));
    EXPECT_EQ(other->map_point_ids(), kf->map_point_ids());
    EXPECT_EQ(other->connection_weights(), kf->connection_weights());
    EXPECT_EQ(other->parent_id(), kf->parent_id());
    EXPECT_TRUE(other->has_bow());
  }
  for (const auto& mp : before->map_points()) {
    const auto other = after->map_point(mp->id());
    ASSERT_TRUE(other) << mp->id();
    EXPECT_EQ(other->observations(), mp->observations());
  }
  EXPECT_EQ(after->next_map_point_id(), before->next_map_point_id() + kPointIdGapAfterRestore)
      << "edge point ids skip past any handed out after the save: never reused";
  EXPECT_EQ(restarted.counters().last_seq, mobile.sent.size()) << "the acknowledgement survives the restart";
  const KeyFrameAccount account_before = edge.keyframe_account(), account_after = restarted.keyframe_account();
  EXPECT_EQ(account_after.inserted, account_before.inserted);
  EXPECT_EQ(account_after.culled, account_before.culled);
  EXPECT_EQ(account_after.in_map, account_before.in_map);
  EXPECT_EQ(account_after.inserted.size(), mobile.sent.size());
  // The mobile resends what it has no acknowledgement for: the restarted edge knows it already.
  EXPECT_EQ(restarted.receive_keyframe(mobile.sent[3], wall_clock_seconds()), KeyFrameVerdict::kDuplicate);
  // The KeyFrame database came back too: a Frame equal to KeyFrame 2 finds candidates.
  FrameRecord frame;
  frame.id = 500;
  frame.camera = mobile.sent[2].camera;
  frame.features = mobile.sent[2].features;
  std::string error;
  EXPECT_TRUE(edge.build_relocalization_update(frame, 1.0, &error)) << "before the restart: " << error;
  EXPECT_TRUE(restarted.build_relocalization_update(frame, 1.0, &error)) << error;
  EXPECT_TRUE(restarted.build_local_map_update(2.0));
}

TEST(EdgePersistence, SavingWhileMappingRunsGivesALoadableFile) {
  const Mobile mobile;
  const std::string busy_path = temp_path("busy.esmap"), path = temp_path("saving.esmap");
  EdgeSession edge(mobile.source.camera, 8, 1.2f, mobile.vocabulary, mobile.params());
  // Each KeyFrame is handed to Local-Mapping and the map saved at once, again and again while
  // the mapping thread works on it (queued or running: not idle). Those saves start while mapping
  // runs (the snapshot is taken under the locks mapping takes); the last such file must load.
  int overlapped = 0;
  for (const KeyFrameRecord& r : mobile.sent) {
    std::string error;
    ASSERT_EQ(edge.receive_keyframe(r, wall_clock_seconds(), &error), KeyFrameVerdict::kInserted) << error;
    while (!edge.mapping_idle()) {
      edge.save_map(path);
      std::rename(path.c_str(), busy_path.c_str());
      ++overlapped;
    }
    ASSERT_TRUE(edge.wait_until_idle(60.0));
  }
  ASSERT_GT(overlapped, 0) << "no save started while Local-Mapping was busy";
  EdgeSession restarted(mobile.source.camera, 8, 1.2f, mobile.vocabulary, mobile.params());
  EXPECT_NO_THROW(restarted.load_map(busy_path)) << "a file saved while mapping ran";
  EXPECT_GT(restarted.global_map()->num_keyframes(), 0u);
  std::remove(busy_path.c_str());
  std::remove(path.c_str());
}

TEST(EdgePersistence, CorruptFileKeepsTheRunningMap) {
  const Mobile mobile;
  const std::string path = temp_path("corrupt.esmap");
  EdgeSession edge(mobile.source.camera, 8, 1.2f, mobile.vocabulary, mobile.params());
  feed(edge, mobile);
  edge.save_map(path);
  const size_t keyframes = edge.global_map()->num_keyframes();
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('\x5a');
  }
  try {
    edge.load_map(path);
    ADD_FAILURE() << "a corrupt map file was loaded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
  EXPECT_EQ(edge.global_map()->num_keyframes(), keyframes);
  EXPECT_THROW(edge.load_map(path), std::runtime_error) << "missing file";
  EXPECT_EQ(edge.global_map()->num_keyframes(), keyframes);
  EXPECT_EQ(edge.receive_keyframe(mobile.sent[0], wall_clock_seconds()), KeyFrameVerdict::kDuplicate) << "the session still works";
}

}  // namespace
}  // namespace edge_slam
