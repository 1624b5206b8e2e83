// The edge's durability (split/edge_durability.h) with injected boot ids and time: what a
// checkpoint makes durable, a restore from it, a corrupt checkpoint kept aside as
// <file>.corrupt-<now> with an empty start, a loaded map as a new session (new boot id), and
// what the acknowledgement carries.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "edge_slam/split/edge_durability.h"
#include "support/sent_keyframes.h"

namespace edge_slam {
namespace {

using test_support::SentKeyFrames;

std::string temp_path(const char* name) {
  return "/tmp/edge_slam_durability_" + std::to_string(::getpid()) + "_" + name;
}

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

// Boot ids 1, 2, 3 ... : a new one on every call, as a restarted edge would draw.
EdgeDurability::BootIds counting_boot_ids() {
  auto next = std::make_shared<uint64_t>(0);
  return [next] { return ++*next; };
}

struct Edge {
  const SentKeyFrames& mobile;
  EdgeSession session;
  EdgeDurability durability;
  Edge(const SentKeyFrames& m, const std::string& checkpoint)
      : mobile(m),
        session(m.source.camera, 8, 1.2f, m.vocabulary, m.params()),
        durability(session, DurabilityParams{checkpoint, 5.0}, counting_boot_ids()) {}
  // One at a time, each once Local-Mapping is done with the previous (condition 2 takes it).
  void receive(size_t count) {
    for (size_t i = 0; i < count; ++i) {
      std::string error;
      ASSERT_EQ(session.receive_keyframe(mobile.sent[i], 0.0, &error), KeyFrameVerdict::kInserted) << error;
      ASSERT_TRUE(session.wait_until_idle(60.0));
    }
  }
};

const SentKeyFrames& mobile() {
  static const SentKeyFrames m;
  return m;
}

TEST(EdgeDurability, ACheckpointMakesWhatWasReceivedDurable) {
  const std::string file = temp_path("checkpoint.esmap");
  Edge edge(mobile(), file);
  EXPECT_EQ(edge.durability.restore(0.0), RestoreResult::kNoCheckpoint);
  edge.receive(4);
  KeyFrameAck a = edge.durability.ack();
  EXPECT_EQ(a.boot_id, 1u);
  EXPECT_TRUE(a.persistent);
  EXPECT_EQ(a.received_seq, 4u);
  EXPECT_EQ(a.durable_seq, 0u) << "nothing durable before the first checkpoint";
  ASSERT_TRUE(edge.durability.checkpoint("periodic", 1.0));
  a = edge.durability.ack();
  EXPECT_EQ(a.durable_seq, 4u);
  EXPECT_EQ(edge.durability.checkpoints(), 1u);
  EXPECT_TRUE(exists(file));
  std::remove(file.c_str());
}

TEST(EdgeDurability, ARestartRestoresTheCheckpointAndAllOfItIsDurable) {
  const std::string file = temp_path("restart.esmap");
  {
    Edge before(mobile(), file);
    before.receive(5);
    ASSERT_TRUE(before.durability.checkpoint("shutdown", 1.0));
  }
  Edge after(mobile(), file);
  EXPECT_EQ(after.durability.restore(2.0), RestoreResult::kRestored);
  EXPECT_EQ(after.durability.durable_seq(), 5u);
  EXPECT_EQ(after.session.global_map()->num_keyframes(), 5u);
  const KeyFrameAck a = after.durability.ack();
  EXPECT_EQ(a.received_seq, 5u);
  EXPECT_EQ(a.durable_seq, 5u);
  std::remove(file.c_str());
}

TEST(EdgeDurability, ACorruptCheckpointIsKeptAsideAndTheEdgeStartsEmpty) {
  const std::string file = temp_path("corrupt.esmap");
  std::ofstream(file) << "not a map file";
  Edge edge(mobile(), file);
  EXPECT_EQ(edge.durability.restore(1234.9), RestoreResult::kCorruptRenamed);
  EXPECT_FALSE(exists(file)) << "the next checkpoint must not overwrite the evidence";
  EXPECT_TRUE(exists(file + ".corrupt-1234"));
  EXPECT_EQ(edge.session.global_map()->num_keyframes(), 0u);
  EXPECT_EQ(edge.durability.durable_seq(), 0u);
  edge.receive(2);
  EXPECT_TRUE(edge.durability.checkpoint("periodic", 1235.0)) << "persistence goes on";
  std::remove(file.c_str());
  std::remove((file + ".corrupt-1234").c_str());
}

TEST(EdgeDurability, ALoadedMapIsANewSessionForTheMobile) {
  const std::string file = temp_path("load.esmap"), other = temp_path("other.esmap");
  Edge edge(mobile(), file);
  edge.receive(3);
  std::string error;
  ASSERT_TRUE(edge.durability.save(other, 1.0, &error)) << error;
  EXPECT_EQ(edge.durability.checkpoints(), 0u) << "a copy elsewhere is not a checkpoint";
  ASSERT_TRUE(edge.durability.save("", 1.0, &error)) << "empty path: the checkpoint file. " << error;
  EXPECT_EQ(edge.durability.checkpoints(), 1u);

  edge.durability.load(other);
  EXPECT_EQ(edge.durability.boot_id(), 2u) << "a new boot id: the mobile resends what the map lacks";
  EXPECT_EQ(edge.durability.durable_seq(), 0u) << "not the checkpoint: nothing durable until the next one";
  edge.durability.load("");
  EXPECT_EQ(edge.durability.boot_id(), 3u);
  EXPECT_EQ(edge.durability.durable_seq(), 3u) << "the checkpoint itself: durable";
  EXPECT_THROW(edge.durability.load(temp_path("missing.esmap")), std::runtime_error);
  std::remove(file.c_str());
  std::remove(other.c_str());
}

TEST(EdgeDurability, WithoutACheckpointFileNothingIsPersistent) {
  Edge edge(mobile(), "");
  EXPECT_EQ(edge.durability.restore(0.0), RestoreResult::kNoCheckpoint);
  edge.receive(2);
  std::string error;
  EXPECT_FALSE(edge.durability.checkpoint("periodic", 1.0, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(edge.durability.save("", 1.0, &error));
  EXPECT_NE(error.find("no path"), std::string::npos) << error;
  EXPECT_THROW(edge.durability.load(""), std::runtime_error);
  const KeyFrameAck a = edge.durability.ack();
  EXPECT_FALSE(a.persistent);
  EXPECT_EQ(a.received_seq, 2u);
}

TEST(EdgeDurability, ProgressIsSeenOnceLocalMappingFinishesAKeyFrame) {
  Edge edge(mobile(), "");
  edge.durability.ack();
  EXPECT_FALSE(edge.durability.mapping_progressed());
  edge.receive(1);  // waits until Local-Mapping is done with it
  EXPECT_TRUE(edge.durability.mapping_progressed());
  EXPECT_EQ(edge.durability.ack().mapped_seq, 1u);
  EXPECT_FALSE(edge.durability.mapping_progressed()) << "acknowledged";
}

}  // namespace
}  // namespace edge_slam
