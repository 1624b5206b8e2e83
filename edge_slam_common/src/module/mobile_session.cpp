#include "edge_slam/module/mobile_session.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <chrono>
#include <unordered_set>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/util/heap_release.h"
#include "edge_slam/util/log.h"
#include "edge_slam/util/robot_ids.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/module/local_map_cap.h"
#include "edge_slam/module/local_mapping_params.h"
#include "edge_slam/module/map_point_culling.h"
#include "edge_slam/module/point_replacements.h"
#include "edge_slam/module/update_carry_over.h"
#include "edge_slam/module/update_merge.h"
#include "edge_slam/util/wall_clock.h"

namespace edge_slam {

MobileSessionParams load_mobile_session_params(const ConfigMap& cfg) {
  MobileSessionParams p;
  p.policy.initial_time_constraint = cfg.get_double_or("edge_slam/initial_time_constraint", 0.3, 0.0, 60.0);
  const LocalMapSize size = load_local_map_size(cfg);
  p.policy.update_size = size.update_size;
  p.local_map_cap = size.cap;
  p.relocalization_frame_period = cfg.get_double_or("edge_slam/relocalization_frame_period", 0.5, 0.0, 60.0);
  using Pacing = MobileSessionParams::KeyFramePacing;
  p.keyframe_pacing = cfg.get_choice<Pacing>("edge_slam/mobile_keyframe_pacing", "edge",
                                             {{"edge", Pacing::kEdge}, {"none", Pacing::kNone}});
  p.update_retry_window = cfg.get_double_or("edge_slam/update_retry_window", 0.5, 0.0, 60.0);
  p.refute_unfound_points = cfg.get_bool_or("edge_slam/refute_unfound_points", true);
  p.release_heap_after_update = cfg.get_bool_or("edge_slam/release_heap_after_update", true);
  p.point_culling = load_local_mapping_params(cfg).point_culling;
  using Install = MobileSessionParams::UpdateInstall;
  p.update_install = cfg.get_choice<Install>(
      "edge_slam/update_install", "merge",
      {{"replace", Install::kReplace}, {"keep_newer", Install::kKeepNewer}, {"merge", Install::kMerge}});
  return p;
}

namespace {
TrackingParams mobile_tracking_params(TrackingParams t, const MobileSessionParams& p) {
  t = for_host(t, TrackerHost::kMobile);
  t.conditions = p.keyframe_pacing == MobileSessionParams::KeyFramePacing::kEdge ? KeyFrameConditionSet::kAll
                                                                                 : KeyFrameConditionSet::kMobile;
  return t;
}
}  // namespace

MobileSession::MobileSession(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& tracking,
                             std::shared_ptr<const BowVocabulary> vocabulary, const MobileSessionParams& params,
                             RgbEncoding encoding, WallClock clock)
    : clock_(std::move(clock)),
      camera_(camera),
      vocabulary_(vocabulary),
      params_(params),
      pyramid_(std::make_shared<ScalePyramid>(ScalePyramid::make(orb.num_levels, orb.scale_factor))),
      map_(std::make_shared<Map>()),
      database_(std::make_shared<KeyFrameDatabase>()),
      outbox_(params.outbox_capacity),
      tracking_(camera, orb, mobile_tracking_params(tracking, params), map_, database_, vocabulary, encoding),
      policy_(params.policy) {
  if (!valid_robot_index(params.robot_index))
    throw std::invalid_argument("robot index " + std::to_string(params.robot_index) + " out of range 0.." +
                                std::to_string(kMaxRobots - 1));
  const IdSpace keyframes = keyframe_id_space(params.robot_index), points = mobile_point_id_space(params.robot_index);
  map_->set_keyframe_id_space(keyframes.first, keyframes.end);
  map_->set_map_point_id_space(points.first, points.end);
  // Runs inside track(), with mutex_ held.
  tracking_.on_new_keyframe = [this](const std::shared_ptr<KeyFrame>& kf) { on_new_keyframe(kf); };
}

void MobileSession::on_new_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  // First the recent points tracking found too rarely: out of the Local-Map (this KeyFrame no
  // longer observes them) and named in the record for the edge's point culling.
  std::vector<uint32_t> refuted;
  if (params_.refute_unfound_points) refuted = refute_unfound_points(*map_, kf->id(), params_.point_culling);
  keyframe_stats_.points_refuted += refuted.size();
  // The points this KeyFrame created travel in full; the others as observations by id.
  std::unordered_set<uint32_t> created;
  for (uint32_t id : kf->map_point_ids()) {
    if (id == kNoId) continue;
    const auto mp = map_->map_point(id);
    if (mp && mp->reference_kf_id() == kf->id() && mp->num_observations() == 1) created.insert(id);
  }
  KeyFrameRecord record = to_record(*kf, *map_, created);
  record.refuted_points = std::move(refuted);
  record.seq = next_keyframe_seq_++;
  const KeyFrameDecisionInput& decision = tracking_.last_keyframe_decision();
  auto count16 = [](int v) { return static_cast<uint16_t>(std::clamp(v, 0, 65535)); };
  record.tracked_points = count16(decision.tracked_points);
  record.reference_points = count16(decision.reference_tracked_points);
  record.tracked_close_points = count16(decision.tracked_close_points);
  record.untracked_close_points = count16(decision.untracked_close_points);
  record.created_wall = clock_();
  newest_keyframe_ = record;
  newest_created_ = kf;
  created_ids_.push_back(kf->id());
  created_seqs_.push_back(record.seq);
  created_set_.insert(kf->id());
  outbox_.push(std::move(record));  // never blocks; a full outbox evicts the oldest (counted)
  last_keyframe_stamp_ = kf->stamp();
  keyframe_since_update_ = true;
  dropped_by_cap_ += enforce_local_map_cap(*map_, database_.get(), params_.local_map_cap,
                                           {kf->id(), tracking_.reference_keyframe_id()}).size();
  note_local_map_size();
}

void MobileSession::note_local_map_size() {
  local_map_peak_ = std::max(local_map_peak_, map_->num_keyframes());
}

TrackingResult MobileSession::track(const cv::Mat& color, const cv::Mat& depth, double stamp) {
  std::shared_ptr<PendingUpdate> retired;  // an applied update's old Local-Map, freed after the lock
  std::lock_guard<std::mutex> lock(mutex_);
  last_stamp_ = stamp;
  newest_created_.reset();
  // Condition 2: the edge's Local-Mapping is idle once it is done with every KeyFrame sent.
  tracking_.set_mapper_idle(edge_mapped_seq_.load() + 1 >= next_keyframe_seq_ && !edge_busy_elsewhere_.load());
  TrackingResult r = tracking_.track_rgbd(color, depth, stamp);
  if (frames_since_update_ < 2) {
    // Instrumentation: the frames right after an update against the one before it.
    log_info(log_text(frames_since_update_ == 0 ? "first" : "second", " frame after update: ", r.diag.path, ", ",
        r.diag.initial_matches, " matches, ", r.inliers, " inliers (the frame before: ", inliers_before_update_,
        "), prediction off ", r.diag.prediction_error_m * 100, " cm ", r.diag.prediction_error_deg, " deg"));
  }
  if (frames_since_update_ < 1000) ++frames_since_update_;
  last_inliers_ = r.inliers;
  if (r.new_keyframe && r.diag.reference_kf_id != kNoId) {
    MobileKeyFrameStats& k = keyframe_stats_;
    const uint32_t bits = r.diag.keyframe_conditions;
    ++k.made;
    k.fewer_than_reference += (bits & kCondFewerThanReference) ? 1 : 0;
    k.needs_close_points += (bits & kCondNeedsClosePoints) ? 1 : 0;
    k.weak_tracking += (bits & kCondWeakTracking) ? 1 : 0;
    k.reference_mobile_made += created_set_.count(r.diag.reference_kf_id) ? 1 : 0;
    k.inliers_sum += static_cast<uint64_t>(std::max(0, r.inliers));
    k.reference_points_sum += static_cast<uint64_t>(std::max(0, r.diag.reference_points));
  }
  retired = recheck_deferred_update(stamp);  // after the frame: an applied update serves the next one
  if (!r.pose_valid) return r;
  if (const auto ref = map_->keyframe(tracking_.reference_keyframe_id()))
    r.frame_anchor = FrameAnchor{stamp, ref->id(), ref->T_cw() * r.T_cw.inverse()};
  if (newest_created_)
    if (const auto parent = map_->keyframe(newest_created_->parent_id()))
      r.keyframe_link = KeyFrameLink{newest_created_->id(), parent->id(), parent->T_cw() * newest_created_->T_wc()};
  return r;
}

TrackingSnapshot MobileSession::snapshot(double now) const {
  TrackingSnapshot s;
  s.initialized = tracking_.state() != TrackingState::kNotInitialized;
  s.lost = tracking_.state() == TrackingState::kLost;
  s.keyframe_since_last_update = keyframe_since_update_;
  s.now = now;
  s.last_keyframe_time = last_keyframe_stamp_;
  s.local_map_keyframes = static_cast<int>(map_->num_keyframes());
  return s;
}

UpdateOutcome MobileSession::apply_update(const MapUpdateRecord& update, double now) {
  // All the linear work first, while tracking runs: tracking pauses only to swap maps.
  auto pending = std::make_shared<PendingUpdate>();
  pending->seq = update.seq;
  pending->last_keyframe_seq = update.last_keyframe_seq;
  UpdateOutcome out;
  const auto stage_start = std::chrono::steady_clock::now();
  try {
    pending->staged = stage_update(update, camera_, pyramid_, vocabulary_.get());
  } catch (const std::exception& e) {
    out.error = e.what();
    out.decision = UpdateDecision::kRejectInvalid;
    std::lock_guard<std::mutex> lock(mutex_);
    policy_.count_invalid();
    return out;
  }
  out.stage_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - stage_start).count();

  std::shared_ptr<PendingUpdate> superseded;  // freed after the lock is released
  std::lock_guard<std::mutex> lock(mutex_);  // pauses tracking
  // A newer periodic update supersedes one still waiting: that one is refused for good.
  if (deferred_update_ && update.kind == MapUpdateKind::kPeriodic) {
    policy_.count(MapUpdateKind::kPeriodic, UpdateDecision::kRejectKeyFrameRate);
    superseded = std::move(deferred_update_);
  }
  out.decision = policy_.evaluate(update.kind, snapshot(now));
  if (out.decision == UpdateDecision::kRejectKeyFrameRate && update.kind == MapUpdateKind::kPeriodic &&
      params_.update_retry_window > 0) {
    deferred_update_ = std::move(pending);
    deferred_since_ = now;
    out.decision = UpdateDecision::kDeferred;
    return out;
  }
  policy_.count(update.kind, out.decision);
  if (out.decision != UpdateDecision::kAccept) return out;
  if (deferred_update_) {  // an accepted relocalization update replaces the map it was for
    policy_.count(MapUpdateKind::kPeriodic, UpdateDecision::kRejectKeyFrameRate);
    superseded = std::move(deferred_update_);
  }
  install(*pending, out);
  return out;
}

std::shared_ptr<MobileSession::PendingUpdate> MobileSession::recheck_deferred_update(double now) {
  if (!deferred_update_) return nullptr;
  UpdateOutcome out;
  out.decision = policy_.evaluate(MapUpdateKind::kPeriodic, snapshot(now));
  // Still within a KeyFrame burst: wait, unless the window is over.
  if (out.decision == UpdateDecision::kRejectKeyFrameRate && now - deferred_since_ <= params_.update_retry_window)
    return nullptr;
  policy_.count(MapUpdateKind::kPeriodic, out.decision);
  if (out.decision == UpdateDecision::kAccept) install(*deferred_update_, out);
  deferred_outcome_.emplace(deferred_update_->seq, out);
  return std::move(deferred_update_);
}

std::optional<std::pair<uint64_t, UpdateOutcome>> MobileSession::take_deferred_outcome() {
  std::lock_guard<std::mutex> lock(mutex_);
  auto out = std::move(deferred_outcome_);
  deferred_outcome_.reset();
  return out;
}

void MobileSession::install(PendingUpdate& pending, UpdateOutcome& out) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<uint32_t> tracked_ids, mobile_kfs_before;
  const uint32_t reference_id = tracking_.reference_keyframe_id();
  const auto reference_before = map_->keyframe(reference_id);
  const Eigen::Isometry3d T_wc_reference_before =
      reference_before ? reference_before->T_wc() : Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> tracked_before;
  std::vector<PointSightings> sightings;  // to follow the points the edge fused (point_replacements.h)
  for (const auto& mp : tracking_.last_frame().map_points)
    if (mp) {
      tracked_ids.push_back(mp->id());
      tracked_before.push_back(mp->position());
      PointSightings s{mp->id(), {}};
      for (const auto& [kf_id, index] : mp->observations()) s.observed_at.emplace_back(kf_id, index);
      sightings.push_back(std::move(s));
    }
  std::unordered_map<uint32_t, uint32_t> replaced_by;
  int followed = 0;
  for (const auto& kf : map_->keyframes())
    if (created_set_.count(kf->id())) mobile_kfs_before.push_back(kf->id());
  if (params_.update_install == MobileSessionParams::UpdateInstall::kMerge) {
    // In place, in time proportional to the update (update_merge.h); the Local-Map's KeyFrames
    // are corrected where they are, so the last frame's reference already carries the correction.
    std::vector<uint32_t> keep;  // within the cap the oldest kept KeyFrames go first, never these
    for (const auto& kf : pending.staged.map->keyframes()) keep.push_back(kf->id());
    keep.push_back(tracking_.reference_keyframe_id());
    if (!created_ids_.empty()) keep.push_back(created_ids_.back());
    {
      std::lock_guard<std::mutex> lock(map_->update_mutex());
      const MergeResult merged = merge_update(*map_, *pending.staged.map, database_.get());
      update_stats_.keyframes_carried += merged.keyframes_kept;
      dropped_by_cap_ += enforce_local_map_cap(*map_, database_.get(), params_.local_map_cap, keep).size();
      replaced_by = find_point_replacements(*map_, sightings);
    }
    followed = tracking_.relink_after_map_update(map_.get(), &replaced_by);
  } else {
    install_update(*map_, pending.staged);  // pending.staged now holds the old Local-Map
    const Map& old_map = *pending.staged.map;
    if (params_.update_install == MobileSessionParams::UpdateInstall::kKeepNewer) {
      std::vector<uint32_t> newer;  // made after the edge built the update, oldest first
      for (size_t i = created_ids_.size(); i-- > 0 && created_seqs_[i] > pending.last_keyframe_seq;)
        newer.insert(newer.begin(), created_ids_[i]);
      std::lock_guard<std::mutex> lock(map_->update_mutex());
      update_stats_.keyframes_carried += carry_over_keyframes(*map_, old_map, newer, nullptr).keyframes;
    }
    database_->clear();
    for (const auto& kf : map_->keyframes())
      if (kf->has_bow()) database_->add(kf);
    {
      std::lock_guard<std::mutex> lock(map_->update_mutex());
      replaced_by = find_point_replacements(*map_, sightings);
    }
    followed = tracking_.relink_after_map_update(&old_map, &replaced_by);
  }
  keyframe_since_update_ = false;
  frames_since_update_ = 0;
  inliers_before_update_ = last_inliers_;
  note_local_map_size();
  double rotation_deg = 0;
  if (const auto reference_after = map_->keyframe(reference_id); reference_after && reference_before) {
    // The reference's change, T_wc(after) * T_wc(before)^-1: its centre's displacement and its turn.
    const Eigen::Isometry3d T_wc_after = reference_after->T_wc();
    const double moved = (T_wc_after.translation() - T_wc_reference_before.translation()).norm();
    update_stats_.max_correction_m = std::max(update_stats_.max_correction_m, moved);
    update_stats_.sum_correction_m += moved;
    rotation_deg = Eigen::AngleAxisd(T_wc_after.rotation() * T_wc_reference_before.rotation().transpose()).angle() *
                   180.0 / M_PI;
    update_stats_.max_reference_rotation_deg = std::max(update_stats_.max_reference_rotation_deg, rotation_deg);
  }
  size_t kept = 0;
  std::vector<double> shifts;
  for (size_t i = 0; i < tracked_ids.size(); ++i)
    if (const auto mp = map_->map_point(tracked_ids[i])) {
      ++kept;
      shifts.push_back((mp->position() - tracked_before[i]).norm());
    }
  double median_shift = 0;
  if (!shifts.empty()) {
    std::nth_element(shifts.begin(), shifts.begin() + shifts.size() / 2, shifts.end());
    median_shift = shifts[shifts.size() / 2];
    update_stats_.max_tracked_point_shift_m = std::max(update_stats_.max_tracked_point_shift_m, median_shift);
  }
  log_info(log_text("update ", pending.seq, " installed: reference KeyFrame ", reference_id, " turned ", rotation_deg,
      " deg; the last frame's points: ", kept, " of ", tracked_ids.size(), " kept, moved ", median_shift * 100,
      " cm (median), ", followed, " followed to the point the edge fused them into"));
  ++update_stats_.installed;
  update_stats_.tracked_points_before += tracked_ids.size();
  update_stats_.tracked_points_kept += kept;
  update_stats_.tracked_points_followed += static_cast<uint64_t>(followed);
  if (!tracked_ids.empty())
    update_stats_.min_kept_share = std::min(update_stats_.min_kept_share, double(kept) / tracked_ids.size());
  for (uint32_t id : mobile_kfs_before) update_stats_.mobile_keyframes_dropped += map_->keyframe(id) ? 0 : 1;
  out.keyframes = pending.staged.stats.keyframes;
  out.map_points = pending.staged.stats.map_points;
  out.rebuild_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (params_.release_heap_after_update) {  // the previous update's map is freed by now
    const HeapRelease released = release_free_heap_pages();
    if (released.supported) {
      ++update_stats_.heap_releases;
      update_stats_.heap_releases_freeing += released.released ? 1 : 0;
      update_stats_.heap_release_ms += released.ms;
      update_stats_.max_heap_release_ms = std::max(update_stats_.max_heap_release_ms, released.ms);
    }
  }
}

void MobileSession::on_edge_progress(uint64_t mapped_seq, bool mapper_busy_elsewhere) {
  edge_busy_elsewhere_ = mapper_busy_elsewhere;
  uint64_t seen = edge_mapped_seq_.load();
  while (mapped_seq > seen && !edge_mapped_seq_.compare_exchange_weak(seen, mapped_seq)) {
  }
}

void MobileSession::count_invalid_update() {
  std::lock_guard<std::mutex> lock(mutex_);
  policy_.count_invalid();
}

std::optional<FrameRecord> MobileSession::take_relocalization_frame(double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (tracking_.state() != TrackingState::kLost) return std::nullopt;
  if (now - last_relocalization_frame_time_ < params_.relocalization_frame_period) return std::nullopt;
  const Frame& f = tracking_.last_frame();
  if (!f.features || f.size() == 0) return std::nullopt;
  last_relocalization_frame_time_ = now;
  FrameRecord r = to_record(f, next_frame_seq_++);
  r.created_wall = clock_();
  return r;
}

bool MobileSession::reset() {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool had_keyframe = newest_keyframe_.has_value();
  if (had_keyframe) {
    KeyFrameRecord r = *newest_keyframe_;
    r.reset = true;
    r.seq = next_keyframe_seq_++;
    outbox_.push(std::move(r));
  }
  tracking_.reset();
  newest_keyframe_.reset();
  keyframe_since_update_ = false;
  if (deferred_update_) policy_.count(MapUpdateKind::kPeriodic, UpdateDecision::kRejectKeyFrameRate);
  deferred_update_.reset();  // it belongs to the map that was just cleared
  return had_keyframe;
}

void MobileSession::set_updates_enabled(bool enabled) {
  std::lock_guard<std::mutex> lock(mutex_);
  policy_.set_enabled(enabled);
}
bool MobileSession::updates_enabled() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return policy_.enabled();
}
MapUpdateCounters MobileSession::update_counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return policy_.counters();
}
double MobileSession::time_constraint() const {
  return policy_.time_constraint(static_cast<int>(map_->num_keyframes()));
}
TrackingState MobileSession::state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tracking_.state();
}
TrackingCounters MobileSession::tracking_counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tracking_.counters();
}
size_t MobileSession::local_map_peak() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return local_map_peak_;
}
uint64_t MobileSession::keyframes_dropped_by_cap() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_by_cap_;
}
std::vector<uint32_t> MobileSession::keyframe_ids_created() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return created_ids_;
}
MobileKeyFrameStats MobileSession::keyframe_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframe_stats_;
}
MobileUpdateStats MobileSession::update_stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return update_stats_;
}
uint64_t MobileSession::keyframes_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return next_keyframe_seq_ - 1;
}

}  // namespace edge_slam
