// The module wiring both deployments share (module/mapping_threads.h): a KeyFrame Local-Mapping
// is done with reaches Loop-Closing, the waits return once both are quiet, a stopped pair
// returns from a wait at once; and EdgeSession's readers of its modules survive the modules
// being replaced by a reset under their feet (they copy the pointer under the session's lock).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "edge_slam/io/map_records.h"
#include "edge_slam/module/mapping_threads.h"
#include "support/sent_keyframes.h"

namespace edge_slam {
namespace {

using test_support::SentKeyFrames;

TEST(MappingThreads, ProcessedKeyFramesGoOnToLoopClosingAndTheWaitsEnd) {
  const SentKeyFrames mobile;
  auto map = std::make_shared<Map>();
  auto database = std::make_shared<KeyFrameDatabase>();
  const auto pyramid = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  MappingThreads threads(map, database, mobile.vocabulary, LocalMappingParams(), LoopClosingParams(), true);
  ASSERT_NE(threads.loop(), nullptr);
  int done = 0;
  threads.mapping().on_keyframe_done = [&done](const std::shared_ptr<KeyFrame>&) { ++done; };
  threads.start();
  for (const KeyFrameRecord& r : mobile.sent) {
    auto kf = keyframe_from_record(r, mobile.source.camera, pyramid);
    {
      std::lock_guard<std::mutex> lock(map->update_mutex());
      for (const NewPointRecord& p : r.new_points) map->add_map_point(map_point_from_new_point(p, *kf));
      map->add_keyframe(kf);
    }
    threads.mapping().insert_keyframe(kf);
  }
  ASSERT_TRUE(threads.wait_until_idle(60.0));
  EXPECT_EQ(done, static_cast<int>(mobile.sent.size()));
  EXPECT_EQ(threads.mapping().stats().keyframes_processed + threads.mapping().stats().keyframes_skipped,
            static_cast<int>(mobile.sent.size()));
  threads.stop(true);
  EXPECT_TRUE(threads.wait_until_idle(0.0)) << "stopped threads do not keep a waiter";
}

TEST(MappingThreads, WithoutLoopClosingOnlyLocalMappingRuns) {
  MappingThreads threads(std::make_shared<Map>(), std::make_shared<KeyFrameDatabase>(), nullptr, LocalMappingParams(),
                         LoopClosingParams(), false);
  EXPECT_EQ(threads.loop(), nullptr);
  threads.start();
  EXPECT_TRUE(threads.wait_until_idle(1.0));
}

// A wait in progress when a reset replaces the modules: it waits on modules that are being
// stopped, so it returns at once, and the modules stay alive until it is done (the old code
// read the session's module pointer without its lock and could use freed memory: make
// test-asan reports that as a heap-use-after-free).
TEST(EdgeSessionModules, AWaitInProgressSurvivesAResetThatReplacesTheModules) {
  const SentKeyFrames mobile;
  EdgeSession edge(mobile.source.camera, 8, 1.2f, mobile.vocabulary, mobile.params());
  // Received long after they were made (backlog): queued for Local-Mapping however busy it is.
  for (KeyFrameRecord r : mobile.sent) {
    r.created_wall = 1.0;
    ASSERT_EQ(edge.receive_keyframe(r, 100.0), KeyFrameVerdict::kInserted);
  }
  std::atomic<bool> waiting{false}, returned{false};
  std::thread waiter([&] {
    waiting = true;
    edge.wait_until_idle(30.0);  // Local-Mapping has six KeyFrames to go through
    returned = true;
  });
  while (!waiting) std::this_thread::yield();
  KeyFrameRecord reset = mobile.sent.front();
  reset.reset = true;
  reset.seq = 100;
  for (int i = 0; i < 20; ++i, ++reset.seq) ASSERT_EQ(edge.receive_keyframe(reset, 0.0), KeyFrameVerdict::kReset);
  const auto start = std::chrono::steady_clock::now();
  waiter.join();
  EXPECT_TRUE(returned);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0)
      << "the wait ended with the modules it waited on, not at its timeout";
  EXPECT_EQ(edge.counters().resets, 20u);
  EXPECT_TRUE(edge.wait_until_idle(5.0)) << "the new modules are idle";
  EXPECT_EQ(edge.global_map()->num_keyframes(), 0u);
}

}  // namespace
}  // namespace edge_slam
