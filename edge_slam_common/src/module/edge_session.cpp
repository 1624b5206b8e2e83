#include "edge_slam/module/edge_session.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/io/map_snapshot.h"
#include "edge_slam/module/local_map_cap.h"
#include "edge_slam/module/tracking_params.h"

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
  const std::string content = cfg.get_string("edge_slam/update_content", "covisible");
  if (content == "newest")
    p.update_content = EdgeSessionParams::UpdateContent::kNewest;
  else if (content == "covisible")
    p.update_content = EdgeSessionParams::UpdateContent::kCovisible;
  else
    throw std::runtime_error(cfg.origin() + ": key 'edge_slam/update_content' has value '" + content +
                             "', expected one of newest, covisible");
  p.keyframe = load_keyframe_decision_params(cfg);  // conditions 1-2: the tracker's own settings
  p.late_keyframe_age = cfg.get_double_or("edge_slam/late_keyframe_age", 1.0, 0.0, 3600.0);
  p.update_period = cfg.get_double_or("edge_slam/update_period", 5.0, 0.05, 3600.0);
  return p;
}

EdgeSession::EdgeSession(const PinholeCamera& camera, int pyramid_levels, float scale_factor,
                         std::shared_ptr<const BowVocabulary> vocabulary, const EdgeSessionParams& params)
    : camera_(camera),
      pyramid_(std::make_shared<ScalePyramid>(ScalePyramid::make(pyramid_levels, scale_factor))),
      vocabulary_(std::move(vocabulary)),
      params_(params),
      map_(std::make_shared<Map>()),
      database_(std::make_shared<KeyFrameDatabase>()) {
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

KeyFrameVerdict EdgeSession::receive_keyframe(const KeyFrameRecord& r, double now, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.received;
  counters_.last_seq = std::max(counters_.last_seq, r.seq);
  receipts_.mark(r.seq);  // whatever the verdict: a resend would get the same one
  if (r.reset) {
    reset_locked();
    ++counters_.resets;
    return KeyFrameVerdict::kReset;
  }
  if (!seen_ids_.insert(r.id).second) {
    ++counters_.duplicates;
    return KeyFrameVerdict::kDuplicate;
  }
  EdgeKeyFrameState state;
  state.any_inserted = any_inserted_;
  state.last_inserted_frame_id = last_inserted_frame_id_;
  state.relocalization_sent = relocalization_sent_;
  state.last_relocalization_frame_id = last_relocalization_frame_id_;
  state.mapper_idle = modules_->mapping().idle();
  switch (decide_edge_keyframe(params_.keyframe, params_.late_keyframe_age, state, r, now)) {
    case EdgeKeyFrameDecision::kRejectCondition1:
      ++counters_.rejected_condition1;
      keep_pending_points(r);
      return KeyFrameVerdict::kRejectedAfterRelocalization;
    case EdgeKeyFrameDecision::kRejectCondition2:
      ++counters_.rejected_condition2;
      keep_pending_points(r);
      return KeyFrameVerdict::kRejectedMapperBusy;
    case EdgeKeyFrameDecision::kInsertLate:
      ++counters_.late_keyframes;
      break;
    case EdgeKeyFrameDecision::kInsert:
      if (!state.mapper_idle && weak_tracking(params_.keyframe, edge_decision_input(state, r)))
        ++counters_.weak_tracking_inserted;
      break;
  }

  std::shared_ptr<KeyFrame> kf;
  std::vector<std::shared_ptr<MapPoint>> new_points;
  try {
    kf = keyframe_from_record(r, camera_, pyramid_);
    for (const NewPointRecord& p : r.new_points) new_points.push_back(map_point_from_new_point(p, *kf));
  } catch (const std::exception& e) {
    ++counters_.invalid;
    if (error) *error = e.what();
    return KeyFrameVerdict::kInvalid;
  }
  {
    std::lock_guard<std::mutex> map_lock(map_->update_mutex());
    for (const auto& mp : new_points) {
      if (map_->map_point(mp->id())) continue;  // already known: keep the edge's version
      map_->add_map_point(mp);
    }
    // Points of refused KeyFrames this one observes join the Global-Map now, with this KeyFrame
    // as their reference. Observations of points the Global-Map does not have at all (culled)
    // are dropped; Local-Mapping links the rest.
    const std::vector<uint32_t> ids = kf->map_point_ids();
    for (size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] == kNoId || map_->map_point(ids[i])) continue;
      const auto pending = pending_points_.find(ids[i]);
      if (pending != pending_points_.end()) {
        pending->second->set_reference_kf_id(kf->id());
        map_->add_map_point(pending->second);
        pending_points_.erase(pending);
        ++counters_.pending_points_adopted;
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
  inserted_ids_.push_back(kf->id());
  last_inserted_frame_id_ = r.frame_id;
  any_inserted_ = true;
  ++counters_.inserted;
  return KeyFrameVerdict::kInserted;
}

void EdgeSession::keep_pending_points(const KeyFrameRecord& r) {
  if (r.new_points.empty() || params_.pending_point_capacity == 0) return;
  std::shared_ptr<const FrameFeatures> features;
  try {
    features = features_from_record(r.features, r.camera, camera_, pyramid_);
  } catch (const std::exception&) {
    return;  // not a usable record: its points cannot be described either
  }
  const KeyFrame source(r.id, r.frame_id, r.stamp, features, r.T_wc.inverse());
  for (const NewPointRecord& p : r.new_points) {
    if (pending_points_.count(p.id)) continue;
    try {
      pending_points_.emplace(p.id, map_point_from_new_point(p, source));
    } catch (const std::exception&) {
      continue;
    }
    pending_order_.push_back(p.id);
  }
  while (pending_order_.size() > params_.pending_point_capacity) {  // oldest first
    pending_points_.erase(pending_order_.front());
    pending_order_.pop_front();
  }
}

uint64_t EdgeSession::mapped_seq() const { return counters().mapped_seq; }

void EdgeSession::skip_keyframes_through(uint64_t floor) {
  std::lock_guard<std::mutex> lock(mutex_);
  receipts_.skip_through(floor);
}

MapUpdateRecord EdgeSession::pack_update(const std::vector<std::shared_ptr<KeyFrame>>& kfs) const {
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
  return u;
}

std::optional<MapUpdateRecord> EdgeSession::build_local_map_update(double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  const size_t n = static_cast<size_t>(params_.update_size);
  std::vector<std::shared_ptr<KeyFrame>> newest;
  std::unordered_set<uint32_t> chosen;
  auto take = [&](const std::shared_ptr<KeyFrame>& kf) {
    if (kf && !kf->is_bad() && newest.size() < n && chosen.insert(kf->id()).second) newest.push_back(kf);
  };
  if (params_.update_content == EdgeSessionParams::UpdateContent::kCovisible) {
    // The newest KeyFrame and its strongest covisibles; the newest others fill up what is left.
    for (auto it = inserted_ids_.rbegin(); it != inserted_ids_.rend() && newest.empty(); ++it) take(map_->keyframe(*it));
    if (!newest.empty())
      for (uint32_t id : newest.front()->best_covisibles(n)) take(map_->keyframe(id));
  }
  for (auto it = inserted_ids_.rbegin(); it != inserted_ids_.rend() && newest.size() < n; ++it)
    take(map_->keyframe(*it));
  if (newest.empty()) return std::nullopt;
  std::sort(newest.begin(), newest.end(), [](const auto& a, const auto& b) { return a->id() < b->id(); });
  MapUpdateRecord u = pack_update(newest);
  u.kind = MapUpdateKind::kPeriodic;
  u.seq = next_update_seq_++;
  u.build_start = now;
  u.last_keyframe_seq = counters_.last_seq;
  ++counters_.updates_built;
  return u;
}

std::optional<MapUpdateRecord> EdgeSession::build_relocalization_update(const FrameRecord& fr, double now,
                                                                        std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!vocabulary_ || vocabulary_->empty()) return std::nullopt;
  Frame frame;
  try {
    frame = Frame(fr.id, fr.stamp, features_from_record(fr.features, fr.camera, camera_, pyramid_));
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return std::nullopt;
  }
  frame.compute_bow(*vocabulary_);
  const auto candidates = database_->detect_relocalization_candidates(frame, *map_);
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
  MapUpdateRecord u = pack_update(kfs);
  u.kind = MapUpdateKind::kRelocalization;
  u.seq = next_update_seq_++;
  u.request_frame_id = fr.id;
  u.build_start = now;
  u.last_keyframe_seq = counters_.last_seq;
  last_relocalization_frame_id_ = fr.id;
  relocalization_sent_ = true;
  ++counters_.relocalization_updates_built;
  return u;
}

void EdgeSession::reset_locked() {
  stop_modules();
  map_->clear();
  database_->clear();
  seen_ids_.clear();
  inserted_ids_.clear();
  pending_points_.clear();
  pending_order_.clear();
  {
    std::lock_guard<std::mutex> culled_lock(culled_mutex_);
    culled_ids_.clear();
    culled_links_.clear();
  }
  any_inserted_ = false;
  relocalization_sent_ = false;
  start_modules();
}

uint64_t EdgeSession::save_map(const std::string& path) const {
  MapSnapshot snapshot;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::lock_guard<std::mutex> map_lock(map_->update_mutex());
    snapshot = snapshot_map(*map_);
    // The contiguous seq, not the highest: a restored edge must not claim the gaps.
    snapshot.last_keyframe_seq = receipts_.contiguous();
    snapshot.received_keyframe_ids.assign(seen_ids_.begin(), seen_ids_.end());
    std::sort(snapshot.received_keyframe_ids.begin(), snapshot.received_keyframe_ids.end());
    snapshot.inserted_keyframe_ids = inserted_ids_;
  }
  {
    std::lock_guard<std::mutex> culled_lock(culled_mutex_);
    snapshot.culled_keyframe_ids = culled_ids_;
  }
  write_map_file(snapshot, path);  // no lock held: receiving and mapping go on meanwhile
  return snapshot.last_keyframe_seq;
}

void EdgeSession::load_map(const std::string& path) {
  // Read, check and build everything before touching the session, so a bad file changes nothing.
  const MapSnapshot snapshot = read_map_file(path);
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
  }
  // The restored KeyFrames and every id received before the save count as received: a
  // resent copy is a duplicate. The accounting continues from the saved one.
  seen_ids_ = std::unordered_set<uint32_t>(snapshot.received_keyframe_ids.begin(),
                                           snapshot.received_keyframe_ids.end());
  last_inserted_frame_id_ = 0;
  for (const auto& kf : map_->keyframes()) {
    seen_ids_.insert(kf->id());
    last_inserted_frame_id_ = std::max<uint64_t>(last_inserted_frame_id_, kf->frame_id());
  }
  inserted_ids_ = snapshot.inserted_keyframe_ids;  // insertion order: the newest go in updates
  pending_points_.clear();
  pending_order_.clear();
  {
    std::lock_guard<std::mutex> culled_lock(culled_mutex_);
    culled_ids_ = snapshot.culled_keyframe_ids;
    culled_links_.clear();  // not in the map file: their frames go through the mobile's chain
  }
  any_inserted_ = !map_->keyframes().empty();
  relocalization_sent_ = false;
  counters_.last_seq = std::max(counters_.last_seq, snapshot.last_keyframe_seq);
  receipts_.restore(snapshot.last_keyframe_seq);
  start_modules();
}

bool EdgeSession::wait_until_idle(double timeout_s) const {
  return modules()->wait_until_idle(timeout_s, 2);
}

EdgeCounters EdgeSession::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  EdgeCounters c = counters_;
  c.received_seq = receipts_.contiguous();
  {
    std::lock_guard<std::mutex> map_lock(mapping_seq_mutex_);
    uint64_t oldest = UINT64_MAX;
    for (const auto& [id, seq] : in_mapping_) oldest = std::min(oldest, seq);
    c.mapped_seq = oldest == UINT64_MAX ? c.received_seq : std::min(c.received_seq, oldest - 1);
  }
  return c;
}
// The modules are replaced on a reset (under mutex_): every reader copies the pointer under mutex_ (modules()).
std::vector<LoopEvent> EdgeSession::loops() const {
  const auto m = modules();
  return m->loop() ? m->loop()->loops() : std::vector<LoopEvent>{};
}

ModuleFigures EdgeSession::module_figures() const {
  const auto m = modules();
  return collect_module_figures(&m->mapping(), m->loop());
}

KeyFrameAccount EdgeSession::keyframe_account() const {
  KeyFrameAccount a;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    a.inserted = inserted_ids_;
    a.received.assign(seen_ids_.begin(), seen_ids_.end());
  }
  // The map before the culled list: a KeyFrame culled in between shows up in both, never in neither.
  for (const auto& kf : map_->keyframes()) a.in_map.push_back(kf->id());
  {
    std::lock_guard<std::mutex> lock(culled_mutex_);
    a.culled = culled_ids_;
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
