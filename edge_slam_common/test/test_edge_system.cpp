// The edge deployment without ROS (split/edge_system.h) with an injected wall clock and boot
// ids: KeyFrames and malformed messages end up counted and in the CSV by column, an update's
// publication is timed from its build start and recorded with what it carries, the KeyFrames
// file holds the Global-Map, and the acknowledgement carries the injected boot id.
#include <gtest/gtest.h>
#include <unistd.h>


#include "edge_slam/io/anchors_file.h"
#include "edge_slam/split/edge_system.h"
#include "support/csv_rows.h"
#include "support/sent_keyframes.h"

namespace edge_slam {
namespace {

using test_support::SentKeyFrames;

using test_support::file_text;

double figure(const Figures& f, const std::string& name) {
  for (size_t i = 0; i < f.names.size(); ++i)
    if (f.names[i] == name) return f.values[i];
  ADD_FAILURE() << name << " missing";
  return -1;
}

// An edge on the mobile's records with its own files under `name` (a test's own folder prefix).
EdgeSystemSettings settings_for(const SentKeyFrames& mobile, const std::string& name) {
  const std::string dir = ::testing::TempDir() + name + "_" + std::to_string(::getpid()) + "_";
  EdgeSystemSettings s;
  s.camera = mobile.source.camera;
  s.session = mobile.params();
  s.vocabulary = mobile.vocabulary;
  s.restore_on_start = false;
  s.files = RunFiles{dir + "events.csv", dir + "metrics.json", "", "", dir + "keyframes.txt"};
  return s;
}

TEST(EdgeSystem, CountsRecordsAndPublishesWhatTheNodeletUsedToDoItself) {
  const SentKeyFrames mobile;
  const EdgeSystemSettings s = settings_for(mobile, "edge_system");
  double wall = 500.0;
  {
    EdgeSystem edge(s, [&wall] { return wall; }, [] { return uint64_t{77}; });
    for (const KeyFrameRecord& r : mobile.sent) {
      EXPECT_EQ(edge.receive_keyframe(r, 45000), KeyFrameVerdict::kInserted);
      ASSERT_TRUE(edge.session().wait_until_idle(60.0));
    }
    edge.reject(EdgeSystem::Topic::kKeyFrames, "keypoint index 7 >= 5", 321);
    edge.reject(EdgeSystem::Topic::kFrames, "frame: 12 bytes left, 40 needed", 12);
    EXPECT_EQ(edge.malformed(EdgeSystem::Topic::kKeyFrames), 1u);
    EXPECT_EQ(edge.malformed(), 2u);

    std::optional<MapUpdateRecord> update = edge.periodic_update();
    ASSERT_TRUE(update.has_value());
    EXPECT_EQ(update->build_start, 500.0);
    wall = 500.02;
    edge.stamp_for_publishing(*update);
    EXPECT_EQ(update->publish_stamp, 500.02);
    wall = 500.05;
    edge.published(*update, 250000, 17.0);

    const KeyFrameAck ack = edge.ack();
    EXPECT_EQ(ack.boot_id, 77u);
    EXPECT_EQ(ack.received_seq, mobile.sent.size());
    EXPECT_FALSE(ack.persistent);
    const Figures f = edge.stats();
    EXPECT_EQ(figure(f, "keyframes_inserted"), static_cast<double>(mobile.sent.size()));
    EXPECT_EQ(figure(f, "messages_invalid"), 2.0);
    EXPECT_EQ(figure(f, "updates_sent"), 1.0);
    EXPECT_NEAR(figure(f, "update_build_ms_last"), 50.0, 1e-6);
    EXPECT_TRUE(edge.new_loops(17.0).empty()) << "six KeyFrames close no loop";
    std::string message;
    EXPECT_FALSE(edge.save_map("", &message)) << "no checkpoint file, no path";
    EXPECT_NE(message.find("no path given"), std::string::npos) << message;
    edge.write_outputs();
  }
  const std::string csv = file_text(s.files.events);
  EXPECT_NE(csv.find(",keyframe,1,45000,"), std::string::npos) << csv.substr(0, 400);
  EXPECT_NE(csv.find(",,inserted,0,"), std::string::npos) << "the verdict in the decision column";
  EXPECT_NE(csv.find(",keyframe,0,321,"), std::string::npos);
  EXPECT_NE(csv.find(",,malformed,0,"), std::string::npos);
  EXPECT_NE(csv.find(",,periodic,,0,6,"), std::string::npos) << "update_sent: kind, keyframes";
  const EdgeKeyFrames keyframes = read_edge_keyframes(s.files.keyframes);
  EXPECT_EQ(keyframes.in_map.size(), mobile.sent.size());
  const std::string metrics = file_text(s.files.metrics);
  EXPECT_NE(metrics.find("\"malformed_keyframes\": {\"keypoint index # >= #\": 1}"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("\"updates_sent\": 1"), std::string::npos);
#if defined(__GLIBC__)
  // One memory reading (the second write_outputs, in the destructor, comes too soon for another):
  // the heap and the map objects alive beside the Global-Map's counts.
  size_t heap_rows = 0;
  for (const auto& r : test_support::read_csv_rows(s.files.events)) {
    if (r.at("event") != "heap") continue;
    ++heap_rows;
    EXPECT_EQ(r.at("detail").rfind("in_use_kb=", 0), 0u) << r.at("detail");
    EXPECT_NE(r.at("detail").find(" keyframes_alive="), std::string::npos) << r.at("detail");
    // edge_slam/edge_release_free_heap (default): the free pages went back after the reading.
    EXPECT_NE(r.at("detail").find(" release_ms="), std::string::npos) << r.at("detail");
    EXPECT_NE(r.at("detail").find(" global_map_keyframes=" + std::to_string(mobile.sent.size()) + " global_map_points="),
              std::string::npos) << r.at("detail");
  }
  EXPECT_EQ(heap_rows, 1u);
#endif
  for (const std::string* p : {&s.files.events, &s.files.metrics, &s.files.keyframes}) std::remove(p->c_str());
}

// An update the divergence trigger sends early is the same periodic update on the wire, but the
// event CSV says why it went out, so a run's log tells the early updates from the timer's.
TEST(EdgeSystem, TheEventLogLabelsAnUpdateSentOnDivergence) {
  const SentKeyFrames mobile;
  EdgeSystemSettings s = settings_for(mobile, "edge_system_divergence");
  s.session.late_keyframe_age = 0;
  s.session.update_trigger.divergence_m = 0.02;
  s.session.update_trigger.min_gap_s = 1.0;
  double wall = 500.0;
  {
    EdgeSystem edge(s, [&wall] { return wall; }, [] { return uint64_t{77}; });
    for (size_t i = 0; i + 1 < mobile.sent.size(); ++i) {
      ASSERT_EQ(edge.receive_keyframe(mobile.sent[i], 45000), KeyFrameVerdict::kInserted);
      ASSERT_TRUE(edge.session().wait_until_idle(60.0));
    }
    // The mobile's last KeyFrame 5 cm off, with the points it made: local BA pulls it back.
    KeyFrameRecord weak = mobile.sent.back();
    const Eigen::Vector3d shift(0.05, 0.0, 0.0);
    weak.T_wc.translation() += shift;
    for (NewPointRecord& p : weak.new_points) p.position += shift.cast<float>();
    ASSERT_EQ(edge.receive_keyframe(weak, 45000), KeyFrameVerdict::kInserted);
    ASSERT_TRUE(edge.session().wait_until_idle(60.0));
    std::optional<MapUpdateRecord> early = edge.divergence_update();
    ASSERT_TRUE(early.has_value()) << "local BA moved the mobile's KeyFrame more than 2 cm";
    EXPECT_EQ(early->kind, MapUpdateKind::kPeriodic) << "on the wire, an update like the timer's";
    edge.published(*early, 250000, 17.0);
    wall = 510.0;
    std::optional<MapUpdateRecord> timed = edge.periodic_update();
    ASSERT_TRUE(timed.has_value());
    edge.published(*timed, 250000, 22.0);
    edge.write_outputs();
  }
  const std::string csv = file_text(s.files.events);
  EXPECT_NE(csv.find(",,divergence,,0,"), std::string::npos) << "the early update, labelled";
  EXPECT_NE(csv.find(",,periodic,,0,"), std::string::npos) << "the timer's update, labelled as before";
  for (const std::string* p : {&s.files.events, &s.files.metrics, &s.files.keyframes}) std::remove(p->c_str());
}

}  // namespace
}  // namespace edge_slam
