// The split's KeyFrame and update rules (issue #14), each checked where it lives:
//   - the edge's conditions 1-2 as a pure function of state, record and time;
//   - the mobile's condition 2 reading the edge's acknowledged Local-Mapping progress;
//   - the points of a refused KeyFrame, kept until a later KeyFrame observes them;
//   - the edge's mapped seq (what the acknowledgement carries);
//   - a covisible update holding the newest KeyFrame and what it sees;
//   - an update sent before the timer when the edge's local BA moved a KeyFrame the mobile made;
//   - an installed update keeping the mobile's newer KeyFrames, moved by the update's
//     correction, and the last frame moving with it (the next prediction stays right).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "edge_slam/module/edge_keyframe_decision.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/update_trigger.h"
#include "edge_slam/util/wall_clock.h"
#include "support/split_fixture.h"

namespace edge_slam {
namespace {

using namespace split_fixture;

KeyFrameRecord decision_record(uint32_t frame_id, int tracked, int reference) {
  KeyFrameRecord r;
  r.frame_id = frame_id;
  r.tracked_points = static_cast<uint16_t>(tracked);
  r.reference_points = static_cast<uint16_t>(reference);
  r.tracked_close_points = 200;  // condition (5) does not hold
  r.untracked_close_points = 10;
  r.created_wall = 1000.0;
  return r;
}

TEST(EdgeKeyFrameDecision, Condition2LetsWeakTrackingPastABusyMapper) {
  const KeyFrameDecisionParams p;  // 20 frames, weak below 0.25 x the reference
  EdgeKeyFrameState busy;
  busy.any_inserted = true;
  busy.last_inserted_frame_id = 100;
  busy.mapper_idle = false;
  const double now = 1000.1;  // 0.1 s after creation: live
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, busy, decision_record(105, 300, 400), now),
            EdgeKeyFrameDecision::kRejectCondition2);
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, busy, decision_record(105, 90, 400), now), EdgeKeyFrameDecision::kInsert)
      << "90 < 0.25 x 400: weak tracking";
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, busy, decision_record(120, 300, 400), now), EdgeKeyFrameDecision::kInsert)
      << "20 frames since the last insertion";
  EdgeKeyFrameState idle = busy;
  idle.mapper_idle = true;
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, idle, decision_record(105, 300, 400), now), EdgeKeyFrameDecision::kInsert);
  // Backlog (created 5 s ago) is taken whatever the mapper does; age 0 paces everything (paper).
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, busy, decision_record(105, 300, 400), 1005.0),
            EdgeKeyFrameDecision::kInsertLate);
  EXPECT_EQ(decide_edge_keyframe(p, 0.0, busy, decision_record(105, 300, 400), 1005.0),
            EdgeKeyFrameDecision::kRejectCondition2);
}

TEST(EdgeKeyFrameDecision, Condition1CountsFromTheAssistedRelocalization) {
  const KeyFrameDecisionParams p;  // 20 frames after a relocalization
  EdgeKeyFrameState s;
  s.relocalization_sent = true;
  s.last_relocalization_frame_id = 200;
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, s, decision_record(210, 300, 400), 1000.1),
            EdgeKeyFrameDecision::kRejectCondition1);
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, s, decision_record(220, 300, 400), 1000.1), EdgeKeyFrameDecision::kInsert);
  EXPECT_EQ(decide_edge_keyframe(p, 1.0, s, decision_record(150, 300, 400), 1000.1), EdgeKeyFrameDecision::kInsert)
      << "made before the relocalization: not affected";
}

int keyframes_made(MobileSession& session, bool edge_keeps_up) {
  const RenderedSequence& seq = sequence();
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
    if (edge_keeps_up) session.on_edge_progress(session.keyframes_sent());  // an edge done at once
  }
  return static_cast<int>(session.keyframes_sent());
}

TEST(MobileKeyFramePacing, TheMobileWaitsForTheEdgesLocalMapping) {
  MobileSession paper = make_session(paper_pacing());
  MobileSession silent_edge = make_session();
  MobileSession fast_edge = make_session();
  const int n_paper = keyframes_made(paper, false);
  const int n_silent = keyframes_made(silent_edge, false);
  const int n_fast = keyframes_made(fast_edge, true);
  // No acknowledgement: a KeyFrame only every 20 frames (or on weak tracking).
  EXPECT_LE(n_silent, 1 + kFrames / 20 + 1);
  EXPECT_GT(n_fast, n_silent) << "an edge that keeps up gets KeyFrames whenever (4)/(5) hold";
  EXPECT_EQ(n_fast, n_paper) << "with Local-Mapping always idle, condition 2 never holds one back";
  // Every record tells the edge what the decision saw.
  std::vector<KeyFrameRecord> sent;
  while (auto r = fast_edge.outbox().try_pop()) sent.push_back(std::move(*r));
  ASSERT_GE(sent.size(), 2u);
  for (size_t i = 1; i < sent.size(); ++i) {
    EXPECT_GT(sent[i].tracked_points, 50) << "KeyFrame " << sent[i].id;
    EXPECT_GT(sent[i].reference_points, 0) << "KeyFrame " << sent[i].id;
  }
}

// KeyFrame records of a paced mobile over the first frames, with the Local-Mapping feedback of
// an edge that keeps up.
std::vector<KeyFrameRecord> recorded_keyframes(int frames) {
  const RenderedSequence& seq = sequence();
  MobileSession mobile = make_session(paper_pacing());
  for (int i = 0; i < frames; ++i) mobile.track(seq.colors[i], seq.depths[i], i / 15.0);
  std::vector<KeyFrameRecord> sent;
  while (auto r = mobile.outbox().try_pop()) sent.push_back(std::move(*r));
  return sent;
}

TEST(EdgeSessionKeyFrames, PointsOfARefusedKeyFrameJoinWithTheNextOneThatSeesThem) {
  const RenderedSequence& seq = sequence();
  std::vector<KeyFrameRecord> sent = recorded_keyframes(30);
  ASSERT_GE(sent.size(), 3u);
  EdgeSessionParams params;
  params.loop_closing = false;
  params.late_keyframe_age = 0;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  const double now = wall_clock_seconds();
  ASSERT_EQ(edge.receive_keyframe(sent[0], now), KeyFrameVerdict::kInserted);
  ASSERT_TRUE(edge.wait_until_idle(30.0));
  // Ask the edge to assist a relocalization at the first KeyFrame's view: condition 1 then
  // refuses KeyFrames made within 20 frames of it.
  FrameRecord lost;
  lost.id = sent[1].frame_id;
  lost.stamp = sent[1].stamp;
  lost.camera = sent[1].camera;
  lost.features = sent[1].features;
  ASSERT_TRUE(edge.build_relocalization_update(lost, now));
  KeyFrameRecord refused = sent[1];
  ASSERT_FALSE(refused.new_points.empty());
  ASSERT_EQ(edge.receive_keyframe(refused, now), KeyFrameVerdict::kRejectedAfterRelocalization);
  for (const NewPointRecord& p : refused.new_points) EXPECT_FALSE(edge.global_map()->map_point(p.id));

  // A later KeyFrame (past condition 1) that observes the refused one's points by id.
  KeyFrameRecord later = refused;
  later.id = sent.back().id + 100;
  later.seq = sent.back().seq + 1;
  later.frame_id = refused.frame_id + 25;
  later.parent_id = sent[0].id;
  later.new_points.clear();
  later.covisibility.clear();
  for (const NewPointRecord& p : refused.new_points) later.observations.emplace_back(p.kp_index, p.id);
  std::string error;
  ASSERT_EQ(edge.receive_keyframe(later, now, &error), KeyFrameVerdict::kInserted) << error;
  // Every pending point joined with the later KeyFrame (counted as it was inserted). Local-Mapping
  // runs at once on that KeyFrame and may fuse some into the first KeyFrame's points before the
  // map is read here (1 run in ~10 saw 406 of 456), so presence is checked for most, not all;
  // without the adoption none would be there.
  EXPECT_EQ(edge.counters().pending_points_adopted, refused.new_points.size());
  size_t adopted = 0;
  for (const NewPointRecord& p : refused.new_points) adopted += edge.global_map()->map_point(p.id) ? 1 : 0;
  EXPECT_GE(adopted, refused.new_points.size() / 2);
  ASSERT_TRUE(edge.wait_until_idle(30.0));
}

TEST(EdgeSessionKeyFrames, MappedSeqFollowsLocalMapping) {
  const RenderedSequence& seq = sequence();
  const std::vector<KeyFrameRecord> sent = recorded_keyframes(40);
  ASSERT_GE(sent.size(), 3u);
  EdgeSessionParams params;
  params.loop_closing = false;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  EXPECT_EQ(edge.mapped_seq(), 0u);
  for (const KeyFrameRecord& r : sent) edge.receive_keyframe(r, wall_clock_seconds());
  EXPECT_LE(edge.mapped_seq(), edge.counters().received_seq);
  ASSERT_TRUE(edge.wait_until_idle(30.0));
  EXPECT_EQ(edge.mapped_seq(), sent.back().seq) << "everything decided and mapped";
  EXPECT_EQ(edge.counters().mapped_seq, sent.back().seq);
}

TEST(EdgeSessionUpdates, ACovisibleUpdateHoldsTheNewestKeyFrameAndItsStrongestNeighbours) {
  const RenderedSequence& seq = sequence();
  const std::vector<KeyFrameRecord> sent = recorded_keyframes(kFrames);
  ASSERT_GE(sent.size(), 8u) << "more KeyFrames than an update holds";
  EdgeSessionParams params;
  params.loop_closing = false;
  params.late_keyframe_age = 0;
  params.update_size = 4;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (const KeyFrameRecord& r : sent) {
    edge.receive_keyframe(r, wall_clock_seconds());
    ASSERT_TRUE(edge.wait_until_idle(30.0));  // an idle mapper each time: every KeyFrame inserted
  }
  const std::optional<MapUpdateRecord> u = edge.build_local_map_update(1.0);
  ASSERT_TRUE(u);
  ASSERT_EQ(u->keyframes.size(), 4u);
  const auto newest = edge.global_map()->keyframe(sent.back().id);
  ASSERT_TRUE(newest);
  std::vector<uint32_t> expected = {newest->id()};
  for (uint32_t id : newest->best_covisibles(3)) expected.push_back(id);
  std::sort(expected.begin(), expected.end());
  std::vector<uint32_t> got;
  for (const KeyFrameRecord& k : u->keyframes) got.push_back(k.id);
  EXPECT_EQ(got, expected);
}

TEST(UpdateTrigger, DueWhenAMobileKeyFrameIsFarAndTheLastUpdateIsNotTooRecent) {
  UpdateTriggerParams p;
  p.divergence_m = 0.02;
  p.min_gap_s = 1.0;
  EXPECT_TRUE(divergence_update_due(p, 0.03, 10.0, std::nullopt)) << "no update yet";
  EXPECT_TRUE(divergence_update_due(p, 0.03, 10.0, 9.0));
  EXPECT_FALSE(divergence_update_due(p, 0.03, 10.0, 9.5)) << "too soon after the last update";
  EXPECT_FALSE(divergence_update_due(p, 0.015, 10.0, 2.0)) << "within what local BA moves a good KeyFrame";
  EXPECT_FALSE(divergence_update_due(p, std::nan(""), 10.0, 2.0));
  p.divergence_m = 0.0;
  EXPECT_FALSE(divergence_update_due(p, 1.0, 10.0, std::nullopt)) << "the paper's prototype: the timer only";
  EXPECT_TRUE(divergence_counts(p, false)) << "all moves count by default";
  p.moves = UpdateTriggerParams::Moves::kCorrections;
  EXPECT_FALSE(divergence_counts(p, false)) << "local BA's moves alone";
  EXPECT_TRUE(divergence_counts(p, true));
}

// The periodic update on the data clock, polled (the nodelet's wall timer reads the bag's clock).
TEST(UpdateTrigger, PeriodicScheduleFiresOncePerPeriodOfDataTime) {
  PeriodicSchedule every5(5.0);
  EXPECT_FALSE(every5.due(100.0)) << "the first poll starts the first period";
  EXPECT_FALSE(every5.due(104.99));
  EXPECT_TRUE(every5.due(105.0));
  EXPECT_FALSE(every5.due(105.05)) << "once per period, however often it is polled";
  EXPECT_TRUE(every5.due(110.02)) << "the next deadline keeps the phase: 110";
  EXPECT_FALSE(every5.due(114.9));
  EXPECT_TRUE(every5.due(131.0)) << "a poll long after the deadline (a stalled clock) fires once";
  EXPECT_FALSE(every5.due(132.0)) << "no burst for the missed periods";
  EXPECT_FALSE(every5.due(135.9));
  EXPECT_TRUE(every5.due(136.0)) << "the period after a late fire starts at that fire";
  EXPECT_FALSE(every5.due(20.0)) << "the clock went back (a bag restarted): start over";
  EXPECT_FALSE(every5.due(24.0));
  EXPECT_TRUE(every5.due(25.0));
}

// The mechanism end to end: the mobile's last KeyFrame (and the points it made) 5 cm off, as a
// weak frame in a fast turn gives; the edge's local BA pulls it onto the map the earlier
// KeyFrames' points hold, and that difference makes an update due at once.
TEST(EdgeSessionUpdates, AnUpdateGoesOutEarlyWhenLocalBAMovesAKeyFrameTheMobileMade) {
  const RenderedSequence& seq = sequence();
  const std::vector<KeyFrameRecord> sent = recorded_keyframes(kFrames);
  ASSERT_GE(sent.size(), 4u);
  EdgeSessionParams params;
  params.loop_closing = false;
  params.late_keyframe_age = 0;
  params.update_trigger.divergence_m = 0.02;
  params.update_trigger.min_gap_s = 1.0;
  EdgeSession edge(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (size_t i = 0; i + 1 < sent.size(); ++i) {
    ASSERT_EQ(edge.receive_keyframe(sent[i], wall_clock_seconds()), KeyFrameVerdict::kInserted);
    ASSERT_TRUE(edge.wait_until_idle(30.0));
  }
  EXPECT_LT(edge.mobile_divergence_m(), 0.02) << "good KeyFrames stay close to where the mobile has them";
  EXPECT_FALSE(edge.build_update_on_divergence(100.0));
  KeyFrameRecord weak = sent.back();
  const Eigen::Vector3d shift(0.05, 0.0, 0.0);
  weak.T_wc.translation() += shift;
  for (NewPointRecord& p : weak.new_points) p.position += shift.cast<float>();
  ASSERT_EQ(edge.receive_keyframe(weak, wall_clock_seconds()), KeyFrameVerdict::kInserted);
  ASSERT_TRUE(edge.wait_until_idle(30.0));
  double divergence = 0.0;
  const std::optional<MapUpdateRecord> u = edge.build_update_on_divergence(100.0, 0, &divergence);
  EXPECT_GT(divergence, 0.03) << "local BA moved the weak KeyFrame back most of the 5 cm";
  ASSERT_TRUE(u);
  EXPECT_EQ(u->kind, MapUpdateKind::kPeriodic);
  bool holds_it = false;
  for (const KeyFrameRecord& k : u->keyframes) holds_it |= k.id == weak.id;
  EXPECT_TRUE(holds_it) << "the update carries the corrected KeyFrame";
  EXPECT_EQ(edge.counters().updates_on_divergence, 1u);
  EXPECT_EQ(edge.mobile_divergence_m(), 0.0) << "after an update the edge no longer knows the mobile's poses";

  // Counting corrections only: local BA's move is measured but sends nothing early.
  params.update_trigger.moves = UpdateTriggerParams::Moves::kCorrections;
  EdgeSession corrections(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (const KeyFrameRecord& r : sent) {
    const KeyFrameRecord& record = r.id == weak.id ? weak : r;
    ASSERT_EQ(corrections.receive_keyframe(record, wall_clock_seconds()), KeyFrameVerdict::kInserted);
    ASSERT_TRUE(corrections.wait_until_idle(30.0));
  }
  divergence = 0.0;
  EXPECT_FALSE(corrections.build_update_on_divergence(100.0, 0, &divergence));
  EXPECT_GT(divergence, 0.03) << "the figure still reports the move";
  EXPECT_EQ(corrections.counters().updates_on_divergence, 0u);
  params.update_trigger.moves = UpdateTriggerParams::Moves::kAll;

  // The paper's prototype (divergence_m = 0): the same KeyFrames, no update before the timer.
  params.update_trigger.divergence_m = 0.0;
  EdgeSession paper(seq.camera, 8, 1.2f, seq.vocabulary, params);
  for (size_t i = 0; i + 1 < sent.size(); ++i) {
    paper.receive_keyframe(sent[i], wall_clock_seconds());
    ASSERT_TRUE(paper.wait_until_idle(30.0));
  }
  paper.receive_keyframe(weak, wall_clock_seconds());
  ASSERT_TRUE(paper.wait_until_idle(30.0));
  EXPECT_GT(paper.mobile_divergence_m(), 0.03);
  EXPECT_FALSE(paper.build_update_on_divergence(100.0));
}

// An update shifted by `shift` (the edge moved the whole map), built from all but the newest
// KeyFrame: that one was made after the edge started building it.
MobileSessionParams install_params(MobileSessionParams::UpdateInstall install) {
  MobileSessionParams params = paper_pacing();
  params.update_install = install;
  params.update_retry_window = 0;  // an update is installed or refused at once
  return params;
}

// Tracks the first `frames` frames of the sequence (each must be tracked); the records sent.
std::vector<KeyFrameRecord> track_and_collect(MobileSession& session, int frames) {
  const RenderedSequence& seq = sequence();
  for (int i = 0; i < frames; ++i)
    EXPECT_TRUE(session.track(seq.colors[i], seq.depths[i], i / 15.0).pose_valid) << "frame " << i;
  std::vector<KeyFrameRecord> sent;
  while (auto r = session.outbox().try_pop()) sent.push_back(std::move(*r));
  return sent;
}

MapUpdateRecord shifted_update_without_the_newest(const std::vector<KeyFrameRecord>& sent, const Eigen::Vector3d& shift) {
  std::vector<KeyFrameRecord> known(sent.begin(), sent.end() - 1);
  MapUpdateRecord u = update_from(known, sequence().camera);
  for (KeyFrameRecord& k : u.keyframes) k.T_wc.translation() += shift;
  for (MapPointRecord& p : u.points) p.position += shift.cast<float>();
  u.seq = 1;
  u.last_keyframe_seq = known.back().seq;
  return u;
}

TEST(MobileUpdates, KeyFramesTheUpdateDoesNotHoldAreKeptAndMovedWithIt) {
  const RenderedSequence& seq = sequence();
  const Eigen::Vector3d shift(0.05, 0, 0);
  using Install = MobileSessionParams::UpdateInstall;
  for (const Install install : {Install::kMerge, Install::kKeepNewer, Install::kReplace}) {
    SCOPED_TRACE(install == Install::kMerge ? "merge" : install == Install::kKeepNewer ? "keep_newer" : "replace");
    MobileSession session = make_session(install_params(install));
    const int first = 30;
    const std::vector<KeyFrameRecord> sent = track_and_collect(session, first);
    ASSERT_FALSE(HasFailure());
    ASSERT_GE(sent.size(), 4u);
    // The update holds only the last three it knew of: the first ones and the newest are not in it.
    std::vector<KeyFrameRecord> recent(sent.end() - 4, sent.end());
    std::map<uint32_t, Eigen::Vector3d> before;
    std::map<uint32_t, Eigen::Vector3d> point_before;
    for (const auto& kf : session.local_map()->keyframes()) before[kf->id()] = kf->T_wc().translation();
    for (const auto& mp : session.local_map()->map_points()) point_before[mp->id()] = mp->position();
    const uint32_t newest = sent.back().id, oldest = sent.front().id;
    const UpdateOutcome out =
        session.apply_update(shifted_update_without_the_newest(recent, shift), (first - 1) / 15.0 + 1.0);
    ASSERT_EQ(out.decision, UpdateDecision::kAccept) << to_string(out.decision);
    const auto map = session.local_map();
    EXPECT_EQ(map->keyframe(newest) != nullptr, install != Install::kReplace) << "made after the update was built";
    EXPECT_EQ(map->keyframe(oldest) != nullptr, install == Install::kMerge) << "older than the update's content";
    for (const auto& kf : map->keyframes()) {
      ASSERT_TRUE(before.count(kf->id()));
      EXPECT_LT((kf->T_wc().translation() - (before[kf->id()] + shift)).norm(), 1e-6) << "KeyFrame " << kf->id();
      for (uint32_t id : kf->map_point_ids()) {
        if (id != kNoId) {
          EXPECT_TRUE(map->map_point(id)) << "KeyFrame " << kf->id() << " point " << id;
        }
      }
    }
    for (const auto& mp : map->map_points()) {  // every point moved with the map, exactly once
      if (point_before.count(mp->id())) {
        EXPECT_LT((mp->position() - (point_before[mp->id()] + shift)).norm(), 1e-5) << "point " << mp->id();
      }
    }
    // The next frame is predicted in the shifted map: the last frame moved with its reference.
    const TrackingResult next = session.track(seq.colors[first], seq.depths[first], first / 15.0);
    ASSERT_TRUE(next.pose_valid) << next.message;
    EXPECT_TRUE(next.diag.has_prediction);
    EXPECT_LT(next.diag.prediction_error_m, 0.02) << "a prediction in the old map would be 5 cm off";
  }
}

// Points the edge culled or fused away are not in the update; the live copies the update's
// KeyFrames observed leave with those KeyFrames instead of staying as points nobody observes
// (they piled up to 60,000 on a 50-KeyFrame Local-Map in the 10-minute run).
TEST(MobileUpdates, PointsTheEdgeDroppedLeaveTheLocalMap) {
  MobileSession session = make_session(install_params(MobileSessionParams::UpdateInstall::kMerge));
  const int first = 30;
  const std::vector<KeyFrameRecord> sent = track_and_collect(session, first);
  ASSERT_FALSE(HasFailure());
  ASSERT_GE(sent.size(), 4u);
  std::vector<KeyFrameRecord> recent(sent.end() - 4, sent.end());
  MapUpdateRecord u = shifted_update_without_the_newest(recent, Eigen::Vector3d::Zero());
  std::set<uint32_t> update_kfs;
  for (const KeyFrameRecord& k : u.keyframes) update_kfs.insert(k.id);
  // The points only the update's KeyFrames observe here: the edge "culled" every second one.
  std::set<uint32_t> dropped;
  bool every_second = false;
  for (const auto& mp : session.local_map()->map_points()) {
    bool only_update = mp->num_observations() > 0;
    for (const auto& [kf_id, idx] : mp->observations()) only_update = only_update && update_kfs.count(kf_id);
    if (only_update && (every_second = !every_second)) dropped.insert(mp->id());
  }
  ASSERT_GT(dropped.size(), 10u);
  for (KeyFrameRecord& k : u.keyframes)
    k.observations.erase(std::remove_if(k.observations.begin(), k.observations.end(),
                                        [&](const auto& o) { return dropped.count(o.second) > 0; }),
                         k.observations.end());
  u.points.erase(std::remove_if(u.points.begin(), u.points.end(), [&](const MapPointRecord& p) { return dropped.count(p.id) > 0; }),
                 u.points.end());
  const UpdateOutcome out = session.apply_update(u, (first - 1) / 15.0 + 1.0);
  ASSERT_EQ(out.decision, UpdateDecision::kAccept) << to_string(out.decision);
  const auto map = session.local_map();
  for (uint32_t id : dropped) EXPECT_FALSE(map->map_point(id)) << "point " << id << " the edge dropped";
  for (const auto& mp : map->map_points()) EXPECT_GT(mp->num_observations(), 0) << "point " << mp->id();
}

}  // namespace
}  // namespace edge_slam
