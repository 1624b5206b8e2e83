// The mobile side without ROS, on frames rendered from the project's synthetic room: KeyFrames
// reach the outbox with the points they created, an edge-style Local-Map update is accepted
// and tracking goes on in the rebuilt Local-Map, the controller blocks updates, reset works.
#include <gtest/gtest.h>

#include <iostream>

#include <opencv2/imgproc.hpp>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/sim/renderer.h"
#include "edge_slam/sim/scene.h"
#include "edge_slam/sim/synthetic_camera.h"
#include "edge_slam/sim/trajectory.h"
#include "support/split_fixture.h"
#include "edge_slam/util/instance_count.h"
#include "edge_slam/util/wall_clock.h"

namespace edge_slam {
namespace {

using namespace split_fixture;

TEST(MobileSession, SendsKeyFramesAppliesAnUpdateAndKeepsTracking) {
  const RenderedSequence& seq = sequence();
  MobileSessionParams params;
  params.update_retry_window = 0;  // the paper's rule: refused on arrival, no retry
  MobileSession session = make_session(paper_pacing(params));
  const int first_half = kFrames - 10;
  for (int i = 0; i < first_half; ++i)
    ASSERT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;

  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  ASSERT_GE(sent.size(), 2u);
  EXPECT_EQ(sent.front().seq, 1u);
  EXPECT_GT(sent.front().new_points.size(), 100u) << "the first KeyFrame creates the initial map";
  EXPECT_FALSE(sent.back().observations.empty()) << "later KeyFrames observe existing points";
  for (const KeyFrameRecord& r : sent)
    for (const NewPointRecord& p : r.new_points) EXPECT_LT(p.id, kEdgePointIdFirst);

  // Right after a KeyFrame the update is refused (rule d); a second later it is applied.
  const MapUpdateRecord update = update_from(sent, seq.camera);
  const double last_stamp = (first_half - 1) / 15.0;
  const UpdateOutcome refused = session.apply_update(update, sent.back().stamp + 0.01);
  EXPECT_EQ(refused.decision, UpdateDecision::kRejectKeyFrameRate);
  const UpdateOutcome applied = session.apply_update(update, last_stamp + 1.0);
  ASSERT_EQ(applied.decision, UpdateDecision::kAccept);
  EXPECT_TRUE(applied.error.empty()) << applied.error;
  EXPECT_EQ(applied.keyframes, sent.size());
  EXPECT_EQ(session.local_map_keyframes(), sent.size());
  // No KeyFrame since: the same update again is redundant (rule c).
  EXPECT_EQ(session.apply_update(update, last_stamp + 2.0).decision, UpdateDecision::kRejectRedundant);

  for (int i = first_half; i < kFrames; ++i)
    EXPECT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
  const MapUpdateCounters c = session.update_counters();
  EXPECT_EQ(c.received, 3u);
  EXPECT_EQ(c.accepted, 1u);
  // The replaced Local-Map's memory goes back to the system once per installed update.
  EXPECT_EQ(session.update_stats().heap_releases, session.update_stats().installed);
}

// The edge fused every point into a survivor with a new id (as its local mapping does with the
// duplicates RGB-D KeyFrames create): the update carries only the survivors. The last frame
// follows its points to them through the KeyFrames that saw them (module/point_replacements.h)
// instead of losing them all, and tracking goes on.
TEST(MobileSession, TheLastFrameFollowsItsPointsToThoseTheEdgeFusedThemInto) {
  const RenderedSequence& seq = sequence();
  MobileSession session = make_session(paper_pacing(MobileSessionParams{}));
  const int first_half = kFrames - 10;
  for (int i = 0; i < first_half; ++i)
    ASSERT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  MapUpdateRecord update = update_from(sent, seq.camera);
  auto fused = [](uint32_t id) { return id == kNoId ? id : (id | kEdgePointIdFirst); };
  for (MapPointRecord& p : update.points) p.id = fused(p.id);
  for (KeyFrameRecord& k : update.keyframes) {
    for (auto& [index, point_id] : k.observations) point_id = fused(point_id);
    for (NewPointRecord& p : k.new_points) p.id = fused(p.id);
  }
  ASSERT_EQ(session.apply_update(update, (first_half - 1) / 15.0 + 1.0).decision, UpdateDecision::kAccept);
  const MobileUpdateStats st = session.update_stats();
  ASSERT_EQ(st.installed, 1u);
  ASSERT_GT(st.tracked_points_before, 50u);
  EXPECT_EQ(st.tracked_points_kept, 0u) << "no point keeps its id";
  EXPECT_GE(st.tracked_points_followed, st.tracked_points_before * 9 / 10)
      << "each tracked point was seen in a KeyFrame the update holds";
  for (int i = first_half; i < kFrames; ++i)
    EXPECT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
}

TEST(MobileSession, GivesNoHeapBackWhenReleaseAfterUpdateIsOff) {
  const RenderedSequence& seq = sequence();
  MobileSessionParams params;
  params.update_retry_window = 0;
  params.release_heap_after_update = false;
  MobileSession session = make_session(paper_pacing(params));
  for (int i = 0; i < kFrames - 10; ++i)
    ASSERT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  ASSERT_GE(sent.size(), 2u);
  ASSERT_EQ(session.apply_update(update_from(sent, seq.camera), (kFrames - 11) / 15.0 + 1.0).decision,
            UpdateDecision::kAccept);
  EXPECT_EQ(session.update_stats().installed, 1u);
  EXPECT_EQ(session.update_stats().heap_releases, 0u);
}

TEST(MobileSession, AnUpdateRefusedOnlyByTheKeyFrameRateIsRetriedOnTheNextFrames) {
  const RenderedSequence& seq = sequence();
  // update_retry_window 0.5 s. KeyFrames paced by the edge's Local-Mapping: an edge that keeps up
  // in the first part (a KeyFrame on most frames), then goes quiet, so the frames after the
  // deferral make none (the next one would be 20 frames later) and the update goes in.
  MobileSession session = make_session();
  const int first_half = kFrames - 12;
  for (int i = 0; i < first_half; ++i) {
    ASSERT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
    session.on_edge_progress(session.keyframes_sent());
  }
  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  MapUpdateRecord first = update_from(sent, seq.camera), second = first;
  first.seq = 7;
  second.seq = 8;

  // Superseded: a newer periodic update replaces the waiting one, which counts as refused by (d).
  EXPECT_EQ(session.apply_update(first, sent.back().stamp + 0.01).decision, UpdateDecision::kDeferred);
  EXPECT_EQ(session.apply_update(second, sent.back().stamp + 0.02).decision, UpdateDecision::kDeferred);
  EXPECT_EQ(session.update_counters().rejected_keyframe_rate, 1u);
  EXPECT_FALSE(session.take_deferred_outcome()) << "nothing decided before the next frame";

  std::optional<std::pair<uint64_t, UpdateOutcome>> outcome;
  for (int i = first_half; i < kFrames && !outcome; ++i) {
    ASSERT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
    outcome = session.take_deferred_outcome();
  }
  ASSERT_TRUE(outcome) << "decided within the 0.5 s window";
  EXPECT_EQ(outcome->first, 8u);
  EXPECT_EQ(outcome->second.decision, UpdateDecision::kAccept) << to_string(outcome->second.decision);
  EXPECT_TRUE(outcome->second.error.empty()) << outcome->second.error;
  EXPECT_EQ(outcome->second.keyframes, sent.size());
  const MapUpdateCounters c = session.update_counters();
  EXPECT_EQ(c.received, 2u);
  EXPECT_EQ(c.accepted, 1u);
  EXPECT_EQ(c.rejected_keyframe_rate, 1u);
  EXPECT_FALSE(session.take_deferred_outcome()) << "reported once";
}

TEST(MobileSession, LocalMapStaysWithinItsCapAndEveryKeyFrameIsStillSent) {
  const RenderedSequence& seq = sequence();
  MobileSessionParams params;
  params.local_map_cap = 3;
  params.keyframe_pacing = MobileSessionParams::KeyFramePacing::kNone;  // many KeyFrames: beyond the cap
  const int64_t keyframes_before = InstanceCount<KeyFrame>::alive(), points_before = InstanceCount<MapPoint>::alive();
  MobileSession session(seq.camera, OrbParams(), TrackingParams(), seq.vocabulary, params, RgbEncoding::kRgb);
  size_t peak = 0;
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
    peak = std::max(peak, session.local_map_keyframes());
  }
  // What the cap dropped is freed: nobody keeps an evicted KeyFrame or its points alive.
  const int64_t keyframes_alive = InstanceCount<KeyFrame>::alive() - keyframes_before;
  const int64_t points_alive = InstanceCount<MapPoint>::alive() - points_before;
  std::cout << "alive " << keyframes_alive << " KeyFrames (Local-Map " << session.local_map_keyframes() << "), "
            << points_alive << " points (Local-Map " << session.local_map_points() << ")\n";
  // Tracking may still hold its reference KeyFrame and the last frame's matched points (at most
  // one per keypoint) after the cap dropped them from the Local-Map.
  EXPECT_LE(keyframes_alive, static_cast<int64_t>(session.local_map_keyframes()) + 1);
  EXPECT_LE(points_alive, static_cast<int64_t>(session.local_map_points() + OrbParams().num_features));
  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  ASSERT_GT(sent.size(), 4u) << "the walk must make more KeyFrames than the cap for this test to mean anything";
  EXPECT_LE(peak, 3u);
  EXPECT_EQ(session.local_map_peak(), peak);
  EXPECT_EQ(session.keyframes_dropped_by_cap(), sent.size() - session.local_map_keyframes());
  for (size_t i = 0; i < sent.size(); ++i) {
    EXPECT_EQ(sent[i].seq, i + 1) << "every KeyFrame reaches the outbox, in order";
    EXPECT_GT(sent[i].created_wall, 1.6e9) << "creation wall time set for the transmit latency";
  }
  // Every point the remaining KeyFrames observe is still in the map: dropping left no dangling links.
  const auto map = session.local_map();
  for (const auto& kf : map->keyframes())
    for (uint32_t id : kf->map_point_ids())
      if (id != kNoId) EXPECT_NE(map->map_point(id), nullptr) << "KeyFrame " << kf->id() << " point " << id;
}

TEST(MobileSession, ControllerBlocksUpdatesAndResetSendsTheFlag) {
  const RenderedSequence& seq = sequence();
  MobileSession session = make_session();
  for (int i = 0; i < 10; ++i) session.track(seq.colors[i], seq.depths[i], i / 15.0);
  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  ASSERT_FALSE(sent.empty());

  session.set_updates_enabled(false);
  EXPECT_EQ(session.apply_update(update_from(sent, seq.camera), 100.0).decision, UpdateDecision::kRejectController);
  EXPECT_EQ(session.update_counters().rejected_controller, 1u);

  EXPECT_TRUE(session.reset());
  const auto reset_record = session.outbox().try_pop();
  ASSERT_TRUE(reset_record);
  EXPECT_TRUE(reset_record->reset);
  EXPECT_EQ(reset_record->id, sent.back().id);
  EXPECT_EQ(session.state(), TrackingState::kNotInitialized);
  EXPECT_EQ(session.local_map_keyframes(), 0u);
  EXPECT_FALSE(session.reset()) << "nothing to reset any more";
}

TEST(MobileSession, OffersRelocalizationFramesOnlyWhileLostAndAtTheirPeriod) {
  const RenderedSequence& seq = sequence();
  MobileSession session = make_session();
  for (int i = 0; i < 5; ++i) session.track(seq.colors[i], seq.depths[i], i / 15.0);
  EXPECT_FALSE(session.take_relocalization_frame(1.0)) << "not lost";
  const cv::Mat blank(480, 640, CV_8UC3, cv::Scalar(90, 90, 90));
  session.track(blank, seq.depths[5], 0.2);
  ASSERT_EQ(session.state(), TrackingState::kLost);
  session.track(seq.elsewhere_color, seq.elsewhere_depth, 0.3);  // features, but nothing mapped
  ASSERT_EQ(session.state(), TrackingState::kLost);
  const std::optional<FrameRecord> frame = session.take_relocalization_frame(1.0);
  ASSERT_TRUE(frame);
  EXPECT_GT(frame->features.size(), 500u);
  EXPECT_FALSE(session.take_relocalization_frame(1.2)) << "within the 0.5 s period";
  EXPECT_TRUE(session.take_relocalization_frame(1.6));
}

// The whole split without ROS: KeyFrames flow mobile -> edge, the edge maps them and sends
// Local-Map updates back, the mobile applies them and keeps tracking.
TEST(SplitSessions, KeyFramesReachTheEdgeAndUpdatesComeBack) {
  const RenderedSequence& seq = sequence();
  MobileSession mobile = make_session();  // KeyFrames paced by the edge's Local-Mapping
  EdgeSessionParams edge_params;
  edge_params.loop_closing = false;  // no loop in 4 s of walking
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, edge_params);

  int applied = 0;
  for (int i = 0; i < kFrames; ++i) {
    ASSERT_TRUE(mobile.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
    while (auto r = mobile.outbox().try_pop()) {
      const KeyFrameVerdict v = edge.receive_keyframe(*r, wall_clock_seconds());
      EXPECT_TRUE(v == KeyFrameVerdict::kInserted || v == KeyFrameVerdict::kRejectedMapperBusy) << to_string(v);
      EXPECT_EQ(edge.receive_keyframe(*r, wall_clock_seconds()), KeyFrameVerdict::kDuplicate);
    }
    mobile.on_edge_progress(edge.mapped_seq());  // what the acknowledgements carry
    if (i % 15 == 14) {  // "every second": wait for the mapper, then build and send an update
      ASSERT_TRUE(edge.wait_until_idle(30.0));
      const std::optional<MapUpdateRecord> update = edge.build_local_map_update(i / 15.0);
      ASSERT_TRUE(update);
      EXPECT_LE(update->keyframes.size(), 6u);
      const UpdateOutcome out = mobile.apply_update(*update, i / 15.0 + 1.0);
      EXPECT_TRUE(out.error.empty()) << out.error;
      if (out.decision == UpdateDecision::kAccept) {
        ++applied;
        // Merged in place (update_install: merge): the update's KeyFrames are all there, the
        // Local-Map KeyFrames it did not hold stay, within the cap.
        for (const KeyFrameRecord& k : update->keyframes)
          EXPECT_TRUE(mobile.local_map()->keyframe(k.id)) << "update KeyFrame " << k.id;
        EXPECT_GE(mobile.local_map_keyframes(), update->keyframes.size());
        EXPECT_LE(mobile.local_map_keyframes(), mobile.local_map_cap());
      }
    }
  }
  const EdgeCounters c = edge.counters();
  EXPECT_GE(c.inserted, 3u);
  EXPECT_EQ(c.duplicates, c.received / 2);
  EXPECT_GE(applied, 2);
  EXPECT_EQ(edge.global_map()->num_keyframes(), c.inserted) << "no KeyFrame culled in 4 s";
  const KeyFrameAccount account = edge.keyframe_account();
  EXPECT_EQ(account.inserted.size(), c.inserted);
  EXPECT_EQ(account.in_map, account.inserted);
  EXPECT_TRUE(account.culled.empty());
  // Points the edge triangulated live in the edge's id space and reached the mobile intact.
  size_t edge_points = 0;
  for (const auto& mp : mobile.local_map()->map_points()) edge_points += mp->id() >= kEdgePointIdFirst;
  EXPECT_GT(edge_points, 0u);

  // A reset on the mobile clears the Global-Map too (paper 4.7.4).
  ASSERT_TRUE(mobile.reset());
  const auto reset_record = mobile.outbox().try_pop();
  ASSERT_TRUE(reset_record);
  EXPECT_EQ(edge.receive_keyframe(*reset_record, wall_clock_seconds()), KeyFrameVerdict::kReset);
  EXPECT_EQ(edge.global_map()->num_keyframes(), 0u);
  EXPECT_TRUE(edge.keyframe_account().inserted.empty());
}

}  // namespace
}  // namespace edge_slam
