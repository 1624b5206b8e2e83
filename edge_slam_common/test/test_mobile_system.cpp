// The mobile deployment without ROS (split/mobile_system.h), with an injected wall clock, on
// frames rendered from the synthetic room: what the nodelet used to do itself now happens here
// and is checked from the files it leaves: one CSV row per frame with its tracking state, the
// anchors of every tracked frame and KeyFrame, both rows of a deferred update (arrival, then its
// outcome, by column), the sender's rows, the rejected inputs counted, metrics.json written.
#include <gtest/gtest.h>
#include <unistd.h>


#include "edge_slam/io/anchors_file.h"
#include "edge_slam/split/mobile_system.h"
#include "support/csv_rows.h"
#include "support/split_fixture.h"

namespace edge_slam {
namespace {

using namespace split_fixture;

using test_support::file_text;
using test_support::read_csv_rows;

struct Files {
  std::string dir = ::testing::TempDir() + "mobile_system_" + std::to_string(::getpid()) + "_";
  RunFiles run{dir + "events.csv", dir + "metrics.json", dir + "trajectory.txt", dir + "anchors.txt", ""};
  ~Files() {
    for (const std::string* p : {&run.events, &run.metrics, &run.trajectory, &run.anchors}) std::remove(p->c_str());
  }
};

MobileSystemSettings settings(const RunFiles& files) {
  MobileSystemSettings s;
  s.session = paper_pacing();  // a KeyFrame whenever conditions 3-5 hold: deferrals happen
  s.session.update_retry_window = 0.5;
  s.vocabulary = sequence().vocabulary;
  s.files = files;
  s.dataset = "synthetic";
  return s;
}

TEST(MobileSystem, RecordsFramesAnchorsAndADeferredUpdateByColumn) {
  const RenderedSequence& seq = sequence();
  Files files;
  double wall = 1000.0;
  {
    MobileSystem system(settings(files.run), [&wall] { return wall; });
    system.start(seq.camera);
    const int first = kFrames - 12;
    int tracked = 0;
    for (int i = 0; i < first; ++i) tracked += system.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid;
    ASSERT_EQ(tracked, first);

    std::vector<KeyFrameRecord> sent;
    while (auto r = system.session()->outbox().try_pop()) sent.push_back(*r);
    ASSERT_GE(sent.size(), 2u);
    EXPECT_EQ(sent.back().created_wall, 1000.0) << "records carry the injected clock's time";
    MapUpdateRecord update = update_from(sent, seq.camera);
    update.seq = 1;
    update.publish_stamp = 999.9;  // 100 ms on the way
    const UpdateOutcome out = system.apply_update(update, 123456, sent.back().stamp + 0.01);
    ASSERT_EQ(out.decision, UpdateDecision::kDeferred) << "a KeyFrame was just made: deferred (rule d + retry)";
    for (int i = first; i < kFrames; ++i) system.track(seq.colors[i], seq.depths[i], i / 15.0);

    system.reject_update("keyframe 3: descriptors hold 33 bytes");
    system.reject_image(ImageProblem::kDepth, "depth image holds no valid value");
    EXPECT_EQ(system.session()->update_counters().rejected_invalid, 1u);
    EXPECT_EQ(system.images_rejected(ImageProblem::kDepth), 1u);
    system.write_outputs();
  }
  const auto rows = read_csv_rows(files.run.events);
  std::vector<std::map<std::string, std::string>> frames, updates;
  for (const auto& r : rows) {
    if (r.at("event") == "frame") frames.push_back(r);
    if (r.at("event") == "update") updates.push_back(r);
  }
  ASSERT_EQ(frames.size(), static_cast<size_t>(kFrames));
  EXPECT_EQ(frames[0].at("state"), "OK");
  EXPECT_EQ(frames[5].at("frame_stamp"), frames[5].at("data_time"));
  EXPECT_EQ(frames[5].at("wall_time"), "1000.000000");
  // How each frame was tracked, for explaining a bad one afterwards (the split has no frame_times.csv).
  EXPECT_EQ(frames[0].at("detail").rfind("path=init ", 0), 0u) << frames[0].at("detail");
  EXPECT_NE(frames[5].at("detail").find("path=motion"), std::string::npos) << frames[5].at("detail");
  EXPECT_NE(frames[5].at("detail").find(" local_map_points="), std::string::npos);
  EXPECT_NE(frames[5].at("detail").find(" prediction_error_cm="), std::string::npos);
  ASSERT_EQ(updates.size(), 2u) << "the arrival, then the outcome of the deferral";
  EXPECT_EQ(updates[0].at("kind"), "periodic");
  EXPECT_EQ(updates[0].at("decision"), "deferred");
  EXPECT_EQ(updates[0].at("deferred"), "0");
  EXPECT_EQ(updates[0].at("bytes"), "123456");
  EXPECT_DOUBLE_EQ(std::stod(updates[0].at("latency_ms")), 100.0);
  EXPECT_EQ(updates[1].at("seq"), "1");
  EXPECT_EQ(updates[1].at("deferred"), "1");
  EXPECT_EQ(updates[1].at("bytes"), "0");
  EXPECT_NE(updates[1].at("decision"), "deferred") << "the final word";
  EXPECT_GE(std::stod(updates[1].at("frame_stamp")), std::stod(updates[0].at("frame_stamp")));

  const MobileAnchors anchors = read_mobile_anchors(files.run.anchors);
  EXPECT_EQ(anchors.frames.size(), static_cast<size_t>(kFrames));
  EXPECT_GE(anchors.keyframes.size(), 1u) << "every KeyFrame after the first is on its parent";
  const std::string metrics = file_text(files.run.metrics);
  EXPECT_NE(metrics.find("\"malformed_updates\": {\"keyframe #: descriptors hold # bytes\": 1}"), std::string::npos)
      << metrics;
  EXPECT_NE(metrics.find("\"camera_frames_dropped\""), std::string::npos);
}

TEST(MobileSystem, TheSenderRecordsWhatItPublishesAndTheFiguresSayIt) {
  const RenderedSequence& seq = sequence();
  Files files;
  double wall = 50.0;
  MobileSystem system(settings(files.run), [&wall] { return wall; });
  EXPECT_TRUE(system.stats().names.empty()) << "no figures before tracking starts";
  system.start(seq.camera);
  for (int i = 0; i < 10; ++i) system.track(seq.colors[i], seq.depths[i], i / 15.0);
  system.sender().take_from(system.session()->outbox(), std::chrono::milliseconds(0), wall);
  const KeyFrameSender::Due due = system.sender().due(wall, true);
  ASSERT_FALSE(due.records.empty());
  for (const auto& r : due.records) system.keyframe_sent(*r, 40000);
  wall = 52.5;
  const Figures f = system.stats();
  auto figure = [&f](const std::string& name) {
    for (size_t i = 0; i < f.names.size(); ++i)
      if (f.names[i] == name) return f.values[i];
    ADD_FAILURE() << name << " missing";
    return -1.0;
  };
  EXPECT_EQ(figure("delivery_sent"), static_cast<double>(due.records.size()));
  EXPECT_EQ(figure("keyframes_sent"), static_cast<double>(due.records.size()));
  EXPECT_EQ(figure("keyframe_bytes_sent"), 40000.0 * due.records.size());
  EXPECT_EQ(figure("link_seconds_since_ack"), -1.0) << "no acknowledgement yet";
  KeyFrameAck ack;
  ack.boot_id = 9;
  ack.received_seq = due.records.back()->seq;
  system.on_ack(ack);
  wall = 53.0;
  EXPECT_DOUBLE_EQ(system.stats().values[system.stats().names.size() - 1], 0.5) << "link_seconds_since_ack, last";
  system.write_outputs();
  size_t sent_rows = 0;
  for (const auto& r : read_csv_rows(files.run.events)) sent_rows += r.at("event") == "keyframe_sent";
  EXPECT_EQ(sent_rows, due.records.size());
}

// What the process keeps alive, apart from RSS (util/heap_usage.h): a "heap" row at most every
// MemorySampleClock::kPeriodS of the wall clock, and the latest reading and the peak in metrics.json, so
// a long run tells live data that grows from pages the allocator keeps.
TEST(MobileSystem, SamplesTheHeapAtItsOwnCadence) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "only glibc reports its heap";
#endif
  const RenderedSequence& seq = sequence();
  Files files;
  double wall = 200.0;
  {
    MobileSystem system(settings(files.run), [&wall] { return wall; });
    system.start(seq.camera);
    system.track(seq.colors[0], seq.depths[0], 0.0);
    system.write_outputs();  // the first reading
    wall += MemorySampleClock::kPeriodS - 1.0;
    system.write_outputs();  // too soon: none
    wall += 1.0;
    system.write_outputs();  // the second
    const std::string metrics = file_text(files.run.metrics);
    EXPECT_NE(metrics.find("\"heap\": {\"samples\": 2, \"in_use_mb\": "), std::string::npos) << metrics;
    wall += 0.5;
  }  // the destructor writes once more: too soon again
  std::vector<std::map<std::string, std::string>> heap;
  for (const auto& r : read_csv_rows(files.run.events))
    if (r.at("event") == "heap") heap.push_back(r);
  ASSERT_EQ(heap.size(), 2u);
  EXPECT_EQ(heap[0].at("wall_time"), "200.000000");
  EXPECT_EQ(heap[1].at("wall_time"), "210.000000");
  for (const auto& r : heap) {
    EXPECT_GT(std::stoull(r.at("bytes")), 1000000ull) << "a tracked frame's map and buffers are in use";
    EXPECT_EQ(r.at("detail").rfind("in_use_kb=" + std::to_string(std::stoull(r.at("bytes")) / 1024) + " kept_free_kb=", 0), 0u)
        << r.at("detail");
    EXPECT_NE(r.at("detail").find(" arena_kb="), std::string::npos);
    EXPECT_NE(r.at("detail").find(" mapped_kb="), std::string::npos);
    // The map objects alive beside what the Local-Map holds (one KeyFrame after the first frame).
    EXPECT_NE(r.at("detail").find(" keyframes_alive="), std::string::npos) << r.at("detail");
    EXPECT_NE(r.at("detail").find(" local_map_keyframes=1 local_map_points="), std::string::npos) << r.at("detail");
  }
}

}  // namespace
}  // namespace edge_slam
