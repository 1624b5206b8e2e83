#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/local_mapping_params.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/io/map_snapshot.h"
#include "edge_slam/module/local_map_cap.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/log.h"
#include "edge_slam/util/robot_ids.h"

namespace edge_slam {

const char* to_string(KeyFrameVerdict v) {
  switch (v) {
    case KeyFrameVerdict::kInserted: return "inserted";
    case KeyFrameVerdict::kDuplicate: return "duplicate";
    case KeyFrameVerdict::kRejectedAfterRelocalization: return "condition 1 (too soon after a relocalization)";
    case KeyFrameVerdict::kRejectedMapperBusy: return "condition 2 (Local-Mapping busy, too soon after the last KeyFrame)";
    case KeyFrameVerdict::kInvalid: return "invalid";
    case KeyFrameVerdict::kReset: return "reset";
  }
  return "unknown";
}

EdgeSessionParams load_edge_session_params(const ConfigMap& cfg) {
  EdgeSessionParams p;
  const LocalMapSize size = load_local_map_size(cfg);
  p.update_size = size.update_size;
  p.max_update_keyframes = size.cap;
  using Content = EdgeSessionParams::UpdateContent;
  p.update_content = cfg.get_choice<Content>("edge_slam/update_content", "covisible",
                                             {{"newest", Content::kNewest}, {"covisible", Content::kCovisible}});
  p.keyframe = load_keyframe_decision_params(cfg);  // conditions 1-2: the tracker's own settings
  p.late_keyframe_age = cfg.get_double_or("edge_slam/late_keyframe_age", 1.0, 0.0, 3600.0);
  p.reanchor_late_keyframes = cfg.get_bool_or("edge_slam/reanchor_late_keyframes", true);
  p.release_free_heap = cfg.get_bool_or("edge_slam/edge_release_free_heap", true);
  p.update_period = cfg.get_double_or("edge_slam/update_period", 5.0, 0.05, 3600.0);
  p.update_trigger.divergence_m = cfg.get_double_or("edge_slam/update_on_divergence", 0.0, 0.0, 10.0);
  using Moves = UpdateTriggerParams::Moves;
  p.update_trigger.moves = cfg.get_choice<Moves>("edge_slam/update_on_divergence_moves", "all",
                                                 {{"all", Moves::kAll}, {"corrections", Moves::kCorrections}});
  p.update_trigger.min_gap_s = cfg.get_double_or("edge_slam/update_min_gap", 1.0, 0.0, 3600.0);
  // The edge hosts Local-Mapping: the same "local_mapping:" section the monolithic runner reads.
  p.mapping = load_local_mapping_params(cfg);
  p.loop.verifier = load_loop_verifier_params(cfg);
  return p;
}

namespace {
int checked_robot_count(int robots) {
  if (robots < 1 || robots > kMaxRobots)
    throw std::invalid_argument("edge session: " + std::to_string(robots) + " robots, expected 1.." +
                                std::to_string(kMaxRobots));
  return robots;
}
}  // namespace

EdgeSession::EdgeSession(const PinholeCamera& camera, int pyramid_levels, float scale_factor,
                         std::shared_ptr<const BowVocabulary> vocabulary, const EdgeSessionParams& params)
    : camera_(camera),
      pyramid_(std::make_shared<ScalePyramid>(ScalePyramid::make(pyramid_levels, scale_factor))),
      vocabulary_(std::move(vocabulary)),
      params_(params),
      map_(std::make_shared<Map>()),
      database_(std::make_shared<KeyFrameDatabase>()),
      robots_(static_cast<size_t>(checked_robot_count(params.robots))),
      frames_(params.robots) {
  map_->set_map_point_id_space(kEdgePointIdFirst, kNoId);
  start_modules();
}

EdgeSession::~EdgeSession() { stop_modules(); }

void EdgeSession::start_modules() {
  auto modules = std::make_shared<MappingThreads>(map_, database_, vocabulary_, params_.mapping, params_.loop,
                                                  params_.loop_closing);
  modules->mapping().on_keyframe_done = [this](const std::shared_ptr<KeyFrame>& kf) {
    std::lock_guard<std::mutex> lock(mapping_seq_mutex_);
    in_mapping_.erase(kf->id());
  };
  modules->mapping().on_keyframes_culled = [this](const std::vector<std::shared_ptr<KeyFrame>>& kfs) {
    std::lock_guard<std::mutex> lock(culled_mutex_);
    for (const auto& kf : kfs) {
      culled_ids_.push_back(kf->id());
      culled_links_.push_back(KeyFrameLink{kf->id(), kf->parent_id(), kf->T_cp().inverse()});
    }
  };
  if (modules->loop()) {
    // Every correction is counted (KeyFrames made before the mobile heard of one are re-anchored,
    // module/late_keyframe_anchor.h); with several robots each robot's frame also follows its anchor.
    modules->loop()->on_map_moved = [this] {
      ++map_moves_;
      if (!multi()) return;
      std::map<uint32_t, Eigen::Isometry3d> poses;
      for (const auto& k : map_->keyframes())
        if (!k->is_bad()) poses.emplace(k->id(), k->T_cw());
      frames_.follow_anchors(poses);
    };
  }
  if (multi()) {  // one robot: one map, the paper's mapping and loop closing as they were
    // Each robot's map is mapped, corrected and merged on its own: a correction holds back the
    // KeyFrames of the map(s) it concerns only.
    modules->mapping().group_of = [this](uint32_t kf_id) { return frames_.group_of(kf_id); };
  }
  if (multi() && modules->loop()) {
    modules->loop()->group_of = [this](uint32_t kf_id) { return frames_.group_of(kf_id); };
    modules->loop()->on_merge = [this](int from, int into, const Eigen::Isometry3d& T) { frames_.merge(from, into, T); };
  }
  modules->start();
  modules_ = std::move(modules);
}

void EdgeSession::stop_modules() {
  if (modules_) modules_->stop(false);
  modules_.reset();
  std::lock_guard<std::mutex> lock(mapping_seq_mutex_);
  in_mapping_.clear();  // what was queued is gone with the modules
}

std::shared_ptr<MappingThreads> EdgeSession::modules() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return modules_;
}

namespace {
// A record must carry the ids of the robot that sent it (util/robot_ids.h): its KeyFrame id and
// the points it creates; the points it only observes may be anyone's (a merged map).
std::string foreign_ids(const KeyFrameRecord& r, int robot) {
  if (!keyframe_id_space(robot).contains(r.id))
    return "KeyFrame id " + std::to_string(r.id) + " is not robot " + std::to_string(robot) + "'s (robot " +
           std::to_string(robot_of_keyframe(r.id)) + "'s ids)";
  const IdSpace points = mobile_point_id_space(robot);
  for (const NewPointRecord& p : r.new_points)
    if (!points.contains(p.id))
      return "new map point id " + std::to_string(p.id) + " is not in robot " + std::to_string(robot) +
             "'s range [" + std::to_string(points.first) + ", " + std::to_string(points.end) + ")";
  return {};
}
}  // namespace

KeyFrameVerdict EdgeSession::receive_keyframe(const KeyFrameRecord& r, double now, std::string* error, int robot) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(robots_.size())) {
    if (error) *error = "robot " + std::to_string(robot) + " is not served (" + std::to_string(robots_.size()) + " robots)";
    return KeyFrameVerdict::kInvalid;
  }
  RobotState& rs = robots_[robot];
  ++rs.counters.received;
  // Another robot's record (or a forged one): its seq is not this robot's to acknowledge.
  if (const std::string foreign = foreign_ids(r, robot); !foreign.empty()) {
    ++rs.counters.invalid;
    ++rs.counters.foreign_ids;
    if (error) *error = foreign;
    return KeyFrameVerdict::kInvalid;
  }
  rs.counters.last_seq = std::max(rs.counters.last_seq, r.seq);
  rs.receipts.mark(r.seq);  // whatever the verdict: a resend would get the same one
  if (r.reset) {
    reset_locked(robot);
    if (multi()) frames_.start_new_map(robot, r.id + 1);  // the mobile's ids go on after a reset
    ++rs.counters.resets;
    return KeyFrameVerdict::kReset;
  }
  if (!rs.seen_ids.insert(r.id).second) {
    ++rs.counters.duplicates;
    return KeyFrameVerdict::kDuplicate;
  }
  // What the mobile's tracking measured holds whether or not this KeyFrame is inserted.
  modules_->mapping().refute_points(r.refuted_points);
  EdgeKeyFrameState state;
  state.any_inserted = rs.any_inserted;
  state.last_inserted_frame_id = rs.last_inserted_frame_id;
  state.relocalization_sent = rs.relocalization_sent;
  state.last_relocalization_frame_id = rs.last_relocalization_frame_id;
  state.mapper_idle = modules_->mapping().idle();
  switch (decide_edge_keyframe(params_.keyframe, params_.late_keyframe_age, state, r, now)) {
    case EdgeKeyFrameDecision::kRejectCondition1:
      ++rs.counters.rejected_condition1;
      keep_pending_points(rs, r);
      return KeyFrameVerdict::kRejectedAfterRelocalization;
    case EdgeKeyFrameDecision::kRejectCondition2:
      ++rs.counters.rejected_condition2;
      keep_pending_points(rs, r);
      return KeyFrameVerdict::kRejectedMapperBusy;
    case EdgeKeyFrameDecision::kInsertLate:
      ++rs.counters.late_keyframes;
      break;
    case EdgeKeyFrameDecision::kInsert:
      if (!state.mapper_idle && weak_tracking(params_.keyframe, edge_decision_input(state, r)))
        ++rs.counters.weak_tracking_inserted;
      break;
  }

  std::shared_ptr<KeyFrame> kf;
  std::vector<std::shared_ptr<MapPoint>> new_points;
  try {
    kf = keyframe_from_record(r, camera_, pyramid_);
    for (const NewPointRecord& p : r.new_points) new_points.push_back(map_point_from_new_point(p, *kf));
  } catch (const std::exception& e) {
    ++rs.counters.invalid;
    if (error) *error = e.what();
    return KeyFrameVerdict::kInvalid;
  }
  {
    std::lock_guard<std::mutex> map_lock(map_->update_mutex());
    // The robot's frame -> the coordinates its map is stored in, read under the map lock: a
    // merge moves the map and re-labels the groups under it, so nothing arrives in between.
    const Eigen::Isometry3d T_group_robot = frames_.placement(robot).T_group_robot;
    // Then, if the mobile made it before hearing of a correction, onto its parent's new pose.
    Eigen::Isometry3d T_move = T_group_robot;
    // What the mobile knows of this KeyFrame: its pose as sent. A re-anchored one keeps its
    // parent's count of corrections, so its children (made in the same stale frame) follow too.
    MobileKeyFrameView own{kf->T_cw(), rs.next_update_seq, map_moves_};
    const auto view = r.parent_id == kNoId ? rs.mobile_views.end() : rs.mobile_views.find(r.parent_id);
    const auto parent = view == rs.mobile_views.end() ? nullptr : map_->keyframe(r.parent_id);
    if (parent && !parent->is_bad()) {
      // Instrumentation: how far edge local BA has moved the parent from the mobile's view.
      if (const auto divergence =
              distance_from_mobile_view(view->second, T_group_robot, rs.next_update_seq, parent->T_wc())) {
        if (*divergence > rs.largest_parent_divergence_m) {
          rs.largest_parent_divergence_m = *divergence;
          log_info(log_text("KeyFrame ", kf->id(), ": its parent ", r.parent_id, " is ", *divergence * 100,
              " cm from where the mobile has it (",
              map_moves_ == view->second.map_moves ? "local BA only" : "after a correction", ")"));
        }
      }
      if (params_.reanchor_late_keyframes)
        if (const auto M = late_keyframe_correction(view->second, T_group_robot, parent->T_cw(), rs.next_update_seq,
                                                    map_moves_)) {
          T_move = *M * T_group_robot;
          own.map_moves = view->second.map_moves;
          ++rs.counters.reanchored_after_correction;
          log_info(log_text("KeyFrame ", kf->id(), " was made before a correction reached the mobile: re-anchored "
              "on its parent ", r.parent_id, " (moved ", M->translation().norm() * 100, " cm)"));
        }
    }
    rs.mobile_views[kf->id()] = own;
    const bool moved = !T_move.isApprox(Eigen::Isometry3d::Identity());
    const uint64_t pass = (uint64_t{1} << 41) + ++transform_passes_;
    if (moved) kf->set_pose(kf->T_cw() * T_move.inverse());
    for (const auto& mp : new_points) {
      if (map_->map_point(mp->id())) continue;  // already known: keep the edge's version
      if (moved) mp->transform_once(T_move, pass);
      map_->add_map_point(mp);
    }
    // Points of refused KeyFrames this one observes join the Global-Map now, with this KeyFrame
    // as their reference. Observations of points the Global-Map does not have at all (culled)
    // are dropped; Local-Mapping links the rest.
    const std::vector<uint32_t> ids = kf->map_point_ids();
    for (size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] == kNoId || map_->map_point(ids[i])) continue;
      const auto pending = rs.pending_points.find(ids[i]);
      if (pending != rs.pending_points.end()) {
        pending->second->set_reference_kf_id(kf->id());
        if (moved) pending->second->transform_once(T_move, pass);
        map_->add_map_point(pending->second);
        rs.pending_points.erase(pending);
        ++rs.counters.pending_points_adopted;
      } else {
        kf->erase_map_point_id(i);
      }
    }
    if (kf->parent_id() != kNoId && !map_->keyframe(kf->parent_id())) kf->set_parent(kNoId);
    map_->add_keyframe(kf);
  }
  {
    std::lock_guard<std::mutex> lock(mapping_seq_mutex_);
    in_mapping_[kf->id()] = r.seq;
  }
  modules_->mapping().insert_keyframe(kf);
  rs.inserted_ids.push_back(kf->id());
  rs.last_inserted_frame_id = r.frame_id;
  rs.any_inserted = true;
  ++rs.counters.inserted;
  return KeyFrameVerdict::kInserted;
}

void EdgeSession::keep_pending_points(RobotState& rs, const KeyFrameRecord& r) {
  if (r.new_points.empty() || params_.pending_point_capacity == 0) return;
  std::shared_ptr<const FrameFeatures> features;
  try {
    features = features_from_record(r.features, r.camera, camera_, pyramid_);
  } catch (const std::exception&) {
    return;  // not a usable record: its points cannot be described either
  }
  const KeyFrame source(r.id, r.frame_id, r.stamp, features, r.T_wc.inverse());
  for (const NewPointRecord& p : r.new_points) {
    if (rs.pending_points.count(p.id)) continue;
    try {
      rs.pending_points.emplace(p.id, map_point_from_new_point(p, source));
    } catch (const std::exception&) {
      continue;
    }
    rs.pending_order.push_back(p.id);
  }
  while (rs.pending_order.size() > params_.pending_point_capacity) {  // oldest first
    rs.pending_points.erase(rs.pending_order.front());
    rs.pending_order.pop_front();
  }
}

uint64_t EdgeSession::mapped_seq(int robot) const { return counters(robot).mapped_seq; }

void EdgeSession::skip_keyframes_through(uint64_t floor, int robot) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot >= 0 && robot < static_cast<int>(robots_.size())) robots_[robot].receipts.skip_through(floor);
}

MapUpdateRecord EdgeSession::pack_update(const std::vector<std::shared_ptr<KeyFrame>>& kfs, int robot) const {
  MapUpdateRecord u;
  std::unordered_map<uint32_t, std::shared_ptr<MapPoint>> points;
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());  // a consistent snapshot
  for (const auto& kf : kfs) {
    u.keyframes.push_back(to_record(*kf, *map_));
    for (uint32_t id : kf->map_point_ids())
      if (id != kNoId && !points.count(id))
        if (auto mp = map_->map_point(id); mp && !mp->is_bad()) points.emplace(id, mp);
  }
  u.points.reserve(points.size());
  for (const auto& [id, mp] : points) u.points.push_back(to_record(*mp));
  // In the robot's own frame: the stored coordinates are its group's (one robot: the same).
  const Eigen::Isometry3d T_group_robot = frames_.placement(robot).T_group_robot;
  if (!T_group_robot.isApprox(Eigen::Isometry3d::Identity())) transform_update(u, T_group_robot.inverse());
  return u;
}

std::optional<MapUpdateRecord> EdgeSession::build_local_map_update(double now, int robot) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(robots_.size())) return std::nullopt;
  return build_local_map_update_locked(robots_[robot], now, robot);
}

double EdgeSession::mobile_divergence_m(int robot) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(robots_.size())) return 0.0;
  return mobile_divergence_locked(robots_[robot], robot).all;
}

EdgeSession::Divergence EdgeSession::mobile_divergence_locked(const RobotState& rs, int robot) const {
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  const Eigen::Isometry3d T_group_robot = frames_.placement(robot).T_group_robot;
  Divergence largest;
  for (const auto& [id, view] : rs.mobile_views) {
    const auto kf = map_->keyframe(id);
    if (!kf || kf->is_bad()) continue;
    const auto d = distance_from_mobile_view(view, T_group_robot, rs.next_update_seq, kf->T_wc());
    if (!d) continue;
    largest.all = std::max(largest.all, *d);
    if (divergence_counts(params_.update_trigger, view.map_moves != map_moves_))
      largest.counted = std::max(largest.counted, *d);
  }
  return largest;
}

std::optional<MapUpdateRecord> EdgeSession::build_update_on_divergence(double now, int robot, double* divergence) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(robots_.size())) return std::nullopt;
  RobotState& rs = robots_[robot];
  const Divergence divergences = mobile_divergence_locked(rs, robot);
  if (divergence) *divergence = divergences.all;
  const double d = divergences.counted;
  if (!divergence_update_due(params_.update_trigger, d, now, rs.last_update_time)) return std::nullopt;
  auto u = build_local_map_update_locked(rs, now, robot);
  if (u) {
    ++rs.counters.updates_on_divergence;
    log_info(log_text("Local-Map update ", u->seq, " sent early: a KeyFrame the mobile made is ", d * 100,
                      " cm from the edge's (edge_slam/update_on_divergence ", params_.update_trigger.divergence_m * 100,
                      " cm)"));
  }
  return u;
}

std::optional<MapUpdateRecord> EdgeSession::build_local_map_update_locked(RobotState& rs, double now, int robot) {
  const size_t n = static_cast<size_t>(params_.update_size);
  std::vector<std::shared_ptr<KeyFrame>> newest;
  std::unordered_set<uint32_t> chosen;
  auto take = [&](const std::shared_ptr<KeyFrame>& kf) {
    if (kf && !kf->is_bad() && newest.size() < n && chosen.insert(kf->id()).second) newest.push_back(kf);
  };
  if (params_.update_content == EdgeSessionParams::UpdateContent::kCovisible) {
    // The newest KeyFrame and its strongest covisibles; the newest others fill up what is left.
    for (auto it = rs.inserted_ids.rbegin(); it != rs.inserted_ids.rend() && newest.empty(); ++it) take(map_->keyframe(*it));
    if (!newest.empty())
      for (uint32_t id : newest.front()->best_covisibles(n)) take(map_->keyframe(id));
  }
  for (auto it = rs.inserted_ids.rbegin(); it != rs.inserted_ids.rend() && newest.size() < n; ++it)
    take(map_->keyframe(*it));
  if (newest.empty()) return std::nullopt;
  std::sort(newest.begin(), newest.end(), [](const auto& a, const auto& b) { return a->id() < b->id(); });
  MapUpdateRecord u = pack_update(newest, robot);
  u.kind = MapUpdateKind::kPeriodic;
  u.seq = rs.next_update_seq++;
  rs.mobile_views.clear();  // the update changes the mobile's poses: none of these views holds any more
  rs.last_update_time = now;
  u.build_start = now;
  u.last_keyframe_seq = rs.counters.last_seq;
  ++rs.counters.updates_built;
  return u;
}

std::optional<MapUpdateRecord> EdgeSession::build_relocalization_update(const FrameRecord& fr, double now,
                                                                        std::string* error, int robot) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(robots_.size())) return std::nullopt;
  RobotState& rs = robots_[robot];
  if (!vocabulary_ || vocabulary_->empty()) return std::nullopt;
  Frame frame;
  try {
    frame = Frame(fr.id, fr.stamp, features_from_record(fr.features, fr.camera, camera_, pyramid_));
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return std::nullopt;
  }
  frame.compute_bow(*vocabulary_);
  auto candidates = database_->detect_relocalization_candidates(frame, *map_);
  if (multi()) {  // only the robot's own map (merged or not): another's coordinates mean nothing to it
    const int group = frames_.placement(robot).group;
    candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                    [&](const auto& c) { return frames_.group_of(c->id()) != group; }),
                     candidates.end());
  }
  if (candidates.empty()) return std::nullopt;
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::unordered_set<uint32_t> included;
  auto include = [&](const std::shared_ptr<KeyFrame>& kf) {
    if (kf && !kf->is_bad() && included.insert(kf->id()).second) kfs.push_back(kf);
  };
  for (const auto& c : candidates) include(c);  // candidates first: they survive the cap
  for (const auto& c : candidates)
    for (uint32_t id : c->best_covisibles(params_.neighbours_per_candidate)) include(map_->keyframe(id));
  if (kfs.size() > params_.max_update_keyframes) kfs.resize(params_.max_update_keyframes);
  MapUpdateRecord u = pack_update(kfs, robot);
  u.kind = MapUpdateKind::kRelocalization;
  u.seq = rs.next_update_seq++;
  rs.mobile_views.clear();  // as after a periodic update
  rs.last_update_time = now;
  u.request_frame_id = fr.id;
  u.build_start = now;
  u.last_keyframe_seq = rs.counters.last_seq;
  rs.last_relocalization_frame_id = fr.id;
  rs.relocalization_sent = true;
  ++rs.counters.relocalization_updates_built;
  return u;
}

void EdgeSession::clear_robot(RobotState& rs) {
  rs.seen_ids.clear();
  rs.inserted_ids.clear();
  rs.pending_points.clear();
  rs.pending_order.clear();
  rs.mobile_views.clear();
  rs.last_update_time.reset();  // a new map: no update gap to honour (and a replayed clock may restart)
  rs.any_inserted = false;
  rs.relocalization_sent = false;
}

// One robot: the Global-Map is the robot's map, cleared with it (paper). Several: only the
// robot's state; its KeyFrames stay in the Global-Map for the others, and its next ones start a
// map of their own (RobotFrames::start_new_map), merged again when it sees a known place.
void EdgeSession::reset_locked(int robot) {
  if (multi()) {
    clear_robot(robots_[robot]);
    return;
  }
  stop_modules();
  map_->clear();
  database_->clear();
  clear_robot(robots_[robot]);
  {
    std::lock_guard<std::mutex> culled_lock(culled_mutex_);
    culled_ids_.clear();
    culled_links_.clear();
  }
  start_modules();
}

std::vector<uint64_t> EdgeSession::save_map(const std::string& path) const {
  MapSnapshot snapshot;
  std::vector<uint64_t> durable;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // The detector's history before the map's update mutex: detection holds the detector's lock
    // while it reads the map, so it is not taken under the map's. A KeyFrame detected in between
    // is harmless (ids only).
    std::vector<LoopGroupRecord> loop_groups;
    std::vector<LoopRobotRecord> loop_robots;
    if (modules_ && modules_->loop()) modules_->loop()->save_detector_to(loop_groups, loop_robots);
    std::lock_guard<std::mutex> map_lock(map_->update_mutex());
    snapshot = snapshot_map(*map_);
    snapshot.loop_groups = std::move(loop_groups);
    snapshot.loop_robots = std::move(loop_robots);
    for (const RobotState& rs : robots_) {
      // The contiguous seq, not the highest: a restored edge must not claim the gaps.
      RobotMapSection section{rs.receipts.contiguous(), {rs.seen_ids.begin(), rs.seen_ids.end()}, rs.inserted_ids};
      std::sort(section.received_keyframe_ids.begin(), section.received_keyframe_ids.end());
      durable.push_back(section.last_keyframe_seq);
      snapshot.robots.push_back(std::move(section));
    }
    if (multi()) {  // where the maps are: under the map lock, as merges move KeyFrames under it
      frames_.save_to(snapshot.epochs, snapshot.groups);
      for (const MergeEvent& e : merges_locked())
        snapshot.merges.push_back(MapMergeRecord{e.current_kf_id, e.loop_kf_id, e.group_from, e.group_into, e.matches,
                                                 e.T_into_from});
    } else {  // one robot: version 1's fields, as before
      snapshot.last_keyframe_seq = snapshot.robots[0].last_keyframe_seq;
      snapshot.received_keyframe_ids = std::move(snapshot.robots[0].received_keyframe_ids);
      snapshot.inserted_keyframe_ids = std::move(snapshot.robots[0].inserted_keyframe_ids);
      snapshot.robots.clear();
    }
  }
  {
    std::lock_guard<std::mutex> culled_lock(culled_mutex_);
    snapshot.culled_keyframe_ids = culled_ids_;
  }
  write_map_file(snapshot, path);  // no lock held: receiving and mapping go on meanwhile
  return durable;
}

void EdgeSession::load_map(const std::string& path) {
  // Read, check and build everything before touching the session, so a bad file changes nothing.
  MapSnapshot snapshot = read_map_file(path);
  const size_t file_robots = snapshot.robots.empty() ? 1 : snapshot.robots.size();
  if (file_robots != robots_.size())
    throw std::runtime_error("map file '" + path + "' holds the deliveries of " + std::to_string(file_robots) +
                             " robot(s); this edge serves " + std::to_string(robots_.size()));
  if (snapshot.robots.empty())
    snapshot.robots.push_back(RobotMapSection{snapshot.last_keyframe_seq, snapshot.received_keyframe_ids,
                                              snapshot.inserted_keyframe_ids});
  RobotFrames frames(robots());
  std::string error;
  if (multi() && !frames.restore(snapshot.epochs, snapshot.groups, &error))
    throw std::runtime_error("map file '" + path + "': " + error);
  MapObjects objects;
  try {
    objects = map_objects_from_snapshot(snapshot, camera_, pyramid_, vocabulary_.get());
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error("map file '" + path + "': " + e.what());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  stop_modules();
  {
    std::lock_guard<std::mutex> map_lock(map_->update_mutex());
    map_->clear();
    install_snapshot(snapshot, objects, *map_, *database_);
    // Points the edge made after this save may already sit in the mobile's Local-Map (sent in
    // an update) and come back in its KeyFrames: never hand their ids out again for new points.
    map_->reserve_ids(0, map_->next_map_point_id() + kPointIdGapAfterRestore);
    if (multi()) frames_.restore(snapshot.epochs, snapshot.groups, nullptr);  // checked above
  }
  for (size_t r = 0; r < robots_.size(); ++r) restore_robot(static_cast<int>(r), snapshot.robots[r]);
  merges_loaded_.clear();
  for (const MapMergeRecord& m : snapshot.merges)  // the correction figures are not in the file
    merges_loaded_.push_back(
        MergeEvent{m.keyframe, m.loop_keyframe, m.group_from, m.group_into, m.matches, m.T_into_from, {}});
  {
    std::lock_guard<std::mutex> culled_lock(culled_mutex_);
    culled_ids_ = snapshot.culled_keyframe_ids;
    culled_links_.clear();  // not in the map file: their frames go through the mobile's chain
  }
  start_modules();
  // Under mutex_, so no KeyFrame reaches the new loop thread before its history is back.
  if (modules_->loop()) modules_->loop()->restore_detector(snapshot.loop_groups, snapshot.loop_robots);
}

// The restored KeyFrames of the robot and every id it sent before the save count as received:
// a resent copy is a duplicate. Its accounting continues from the saved one.
void EdgeSession::restore_robot(int robot, const RobotMapSection& section) {
  RobotState& rs = robots_[robot];
  rs.seen_ids = std::unordered_set<uint32_t>(section.received_keyframe_ids.begin(), section.received_keyframe_ids.end());
  rs.last_inserted_frame_id = 0;
  rs.any_inserted = false;
  for (const auto& kf : map_->keyframes()) {
    if (multi() && robot_of_keyframe(kf->id()) != robot) continue;
    rs.seen_ids.insert(kf->id());
    rs.last_inserted_frame_id = std::max<uint64_t>(rs.last_inserted_frame_id, kf->frame_id());
    rs.any_inserted = true;
  }
  rs.inserted_ids = section.inserted_keyframe_ids;  // insertion order: the newest go in updates
  rs.pending_points.clear();
  rs.pending_order.clear();
  rs.relocalization_sent = false;
  rs.counters.last_seq = std::max(rs.counters.last_seq, section.last_keyframe_seq);
  rs.receipts.restore(section.last_keyframe_seq);
}

bool EdgeSession::wait_until_idle(double timeout_s) const {
  return modules()->wait_until_idle(timeout_s, 2);
}

EdgeCounters EdgeSession::counters(int robot) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(robots_.size())) return {};
  EdgeCounters c = robots_[robot].counters;
  c.received_seq = robots_[robot].receipts.contiguous();
  {
    std::lock_guard<std::mutex> map_lock(mapping_seq_mutex_);
    uint64_t oldest = UINT64_MAX;
    for (const auto& [id, seq] : in_mapping_) {
      if (robot_of_keyframe(id) == robot)
        oldest = std::min(oldest, seq);
      else
        c.mapper_busy_elsewhere = true;
    }
    c.mapped_seq = oldest == UINT64_MAX ? c.received_seq : std::min(c.received_seq, oldest - 1);
  }
  return c;
}
// The modules are replaced on a reset (under mutex_): every reader copies the pointer under mutex_ (modules()).
std::vector<LoopEvent> EdgeSession::loops() const {
  const auto m = modules();
  return m->loop() ? m->loop()->loops() : std::vector<LoopEvent>{};
}
std::vector<MergeEvent> EdgeSession::merges(size_t* loaded) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (loaded) *loaded = merges_loaded_.size();
  return merges_locked();
}
std::vector<MergeEvent> EdgeSession::merges_locked() const {
  std::vector<MergeEvent> all = merges_loaded_;
  if (modules_ && modules_->loop()) {
    const std::vector<MergeEvent> live = modules_->loop()->merges();
    all.insert(all.end(), live.begin(), live.end());
  }
  return all;
}

ModuleFigures EdgeSession::module_figures() const {
  const auto m = modules();
  return collect_module_figures(&m->mapping(), m->loop());
}

KeyFrameAccount EdgeSession::keyframe_account(int robot) const {
  KeyFrameAccount a;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (robot < 0 || robot >= static_cast<int>(robots_.size())) return a;
    a.inserted = robots_[robot].inserted_ids;
    a.received.assign(robots_[robot].seen_ids.begin(), robots_[robot].seen_ids.end());
  }
  // The map before the culled list: a KeyFrame culled in between shows up in both, never in neither.
  const auto own = [&](uint32_t id) { return robot_of_keyframe(id) == robot; };
  for (const auto& kf : map_->keyframes())
    if (own(kf->id())) a.in_map.push_back(kf->id());
  {
    std::lock_guard<std::mutex> lock(culled_mutex_);
    for (uint32_t id : culled_ids_)
      if (own(id)) a.culled.push_back(id);
  }
  std::sort(a.inserted.begin(), a.inserted.end());
  std::sort(a.culled.begin(), a.culled.end());
  std::sort(a.in_map.begin(), a.in_map.end());
  std::sort(a.received.begin(), a.received.end());
  return a;
}

EdgeKeyFrames EdgeSession::keyframe_poses() const {
  EdgeKeyFrames k;
  for (const auto& kf : map_->keyframes()) k.in_map.push_back(KeyFramePose{kf->id(), kf->stamp(), kf->T_wc()});
  std::lock_guard<std::mutex> lock(culled_mutex_);
  k.culled = culled_links_;
  return k;
}

int EdgeSession::loops_closed() const {
  const auto m = modules();
  return m->loop() ? m->loop()->loops_closed() : 0;
}
bool EdgeSession::mapping_idle() const {
  return modules()->mapping().idle();
}

}  // namespace edge_slam
