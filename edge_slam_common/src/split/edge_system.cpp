#include "edge_slam/split/edge_system.h"

#include "edge_slam/io/config_file.h"
#include "edge_slam/io/metrics_json.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/heap_release.h"
#include "edge_slam/util/heap_usage.h"
#include "edge_slam/util/log.h"
#include "edge_slam/util/robot_ids.h"

#include <algorithm>
#include <sstream>

namespace edge_slam {

EdgeSystemSettings load_edge_system_settings(const ConfigMap& slam) {
  EdgeSystemSettings s;
  s.orb = load_orb_params(slam);
  s.session = load_edge_session_params(slam);
  s.durability.checkpoint_period = load_checkpoint_period(slam);
  return s;
}


EdgeSystem::EdgeSystem(EdgeSystemSettings settings, WallClock clock, EdgeDurability::BootIds boot_ids)
    : settings_(std::move(settings)),
      clock_(std::move(clock)),
      recorder_(settings_.files, clock_),
      session_(std::make_unique<EdgeSession>(settings_.camera, settings_.orb.num_levels, settings_.orb.scale_factor,
                                             settings_.vocabulary, settings_.session)),
      durability_(*session_, settings_.durability, std::move(boot_ids)),
      update_latency_by_robot_(static_cast<size_t>(session_->robots())),
      keyframe_latency_by_robot_(static_cast<size_t>(session_->robots())) {
  if (settings_.restore_on_start && durability_.persistent()) durability_.restore(clock_());
  rebase_announcements();
}

void EdgeSystem::rebase_announcements() {
  std::lock_guard<std::mutex> lock(announce_mutex_);
  loops_announced_ = session_->loops().size();
  merges_announced_ = 0;  // the loaded file's merges: told again, as restored (new_merges)
}

EdgeSystem::~EdgeSystem() {
  checkpoint("shutdown");
  write_outputs();
}

EventRow EdgeSystem::row(const char* event, double data_time) const {
  EventRow r;
  r.event = event;
  r.data_time = data_time;
  r.map_keyframes = static_cast<long>(session_->global_map()->num_keyframes());
  return r;
}

uint64_t EdgeSystem::malformed(Topic topic) const {
  return (topic == Topic::kKeyFrames ? malformed_keyframes_ : malformed_frames_).total();
}

void EdgeSystem::reject(Topic topic, const std::string& why, size_t bytes) {
  (topic == Topic::kKeyFrames ? malformed_keyframes_ : malformed_frames_).reject(why, clock_());
  EventRow e = row(topic == Topic::kKeyFrames ? "keyframe" : "frame", -1);
  e.bytes = bytes;
  e.decision = "malformed";
  recorder_.event(std::move(e));
}

KeyFrameVerdict EdgeSystem::receive_keyframe(const KeyFrameRecord& record, size_t bytes, int robot) {
  // Created on the mobile (its wall clock) -> received and deserialised here.
  const double latency_ms = (clock_() - record.created_wall) * 1e3;
  {
    std::lock_guard<std::mutex> lock(figures_mutex_);
    keyframe_latency_ms_.push_back(latency_ms);
    if (robot >= 0 && robot < robots()) keyframe_latency_by_robot_[robot].push_back(latency_ms);
    keyframe_bytes_ += bytes;
  }
  std::string error;
  const KeyFrameVerdict v = session_->receive_keyframe(record, clock_(), &error, robot);
  EventRow e = row("keyframe", record.stamp);
  e.seq = record.seq;
  e.bytes = bytes;
  e.latency_ms = latency_ms;
  e.decision = to_string(v);
  recorder_.event(std::move(e));
  if (v == KeyFrameVerdict::kInvalid && invalid_keyframe_log_.allow(clock_()))
    log_error("KeyFrame " + std::to_string(record.id) + (robots() > 1 ? " of robot " + std::to_string(robot) : "") +
              " refused: " + error);
  else if (v == KeyFrameVerdict::kReset)
    log_warn(robots() > 1 ? "reset requested by robot " + std::to_string(robot) + " (KeyFrame " +
                                std::to_string(record.id) + "): its next KeyFrames start a new map"
                          : "reset requested by the mobile (KeyFrame " + std::to_string(record.id) +
                                "): Global-Map cleared");
  else
    log_debug("KeyFrame " + std::to_string(record.id) + ": " + to_string(v));
  return v;
}

std::optional<MapUpdateRecord> EdgeSystem::answer_frame(const FrameRecord& frame, size_t bytes, int robot) {
  const double latency_ms = (clock_() - frame.created_wall) * 1e3;
  std::string error;
  auto update = session_->build_relocalization_update(frame, clock_(), &error, robot);
  if (!error.empty() && refused_frame_log_.allow(clock_()))
    log_error("Frame " + std::to_string(frame.id) + " refused: " + error);
  EventRow e = row("frame", frame.stamp);
  e.seq = frame.seq;
  e.bytes = bytes;
  e.latency_ms = latency_ms;
  e.decision = update ? "answered" : (error.empty() ? "no candidates" : "refused");
  recorder_.event(std::move(e));
  return update;
}

std::optional<MapUpdateRecord> EdgeSystem::periodic_update(int robot) {
  return session_->build_local_map_update(clock_(), robot);
}

std::optional<MapUpdateRecord> EdgeSystem::divergence_update(int robot) {
  double divergence = 0.0;
  auto update = session_->build_update_on_divergence(clock_(), robot, &divergence);
  std::lock_guard<std::mutex> lock(figures_mutex_);
  divergence_cm_.push_back(divergence * 100.0);
  if (update) divergence_pending_.emplace(robot, update->seq);
  return update;
}

void EdgeSystem::stamp_for_publishing(MapUpdateRecord& update) const { update.publish_stamp = clock_(); }

void EdgeSystem::published(const MapUpdateRecord& update, size_t bytes, double data_now, int robot) {
  const double build_ms = (clock_() - update.build_start) * 1e3;
  bool on_divergence = false;
  {
    std::lock_guard<std::mutex> lock(figures_mutex_);
    on_divergence = divergence_pending_.erase({robot, update.seq}) > 0;
    update_build_ms_.push_back(build_ms);
    if (robot >= 0 && robot < robots()) update_latency_by_robot_[robot].push_back(build_ms);
    update_bytes_ += bytes;
    ++updates_sent_;
  }
  EventRow e = row("update_sent", data_now);
  e.seq = update.seq;
  e.bytes = bytes;
  e.duration_ms = build_ms;
  e.kind = update.kind == MapUpdateKind::kRelocalization ? "relocalization" : (on_divergence ? "divergence" : "periodic");
  e.keyframes = static_cast<long>(update.keyframes.size());
  e.points = static_cast<long>(update.points.size());
  if (robots() > 1) e.detail = "robot " + std::to_string(robot);
  recorder_.event(std::move(e));
}

std::vector<std::string> EdgeSystem::new_loops(double data_now) {
  std::lock_guard<std::mutex> lock(announce_mutex_);
  const std::vector<LoopEvent> loops = session_->loops();
  if (loops.size() < loops_announced_) loops_announced_ = 0;
  std::vector<std::string> lines;
  for (size_t i = loops_announced_; i < loops.size(); ++i) {
    lines.push_back("loop closed: KeyFrame " + std::to_string(loops[i].current_kf_id) + " <-> KeyFrame " +
                    std::to_string(loops[i].loop_kf_id) + " (" + std::to_string(loops[i].matches) + " matches)");
    log_info(lines.back());
    EventRow e = row("loop", data_now);
    e.seq = loops[i].current_kf_id;
    e.detail = lines.back();
    recorder_.event(std::move(e));
  }
  loops_announced_ = loops.size();
  return lines;
}

std::vector<MergeEvent> EdgeSystem::new_merges(double data_now) {
  std::lock_guard<std::mutex> lock(announce_mutex_);
  size_t restored_count = 0;
  const std::vector<MergeEvent> merges = session_->merges(&restored_count);
  if (merges.size() < merges_announced_) merges_announced_ = 0;
  std::vector<MergeEvent> fresh;
  for (size_t i = merges_announced_; i < merges.size(); ++i) {
    const MergeEvent& m = merges[i];
    fresh.push_back(m);
    const bool restored = i < restored_count;
    const std::string line = std::string(restored ? "maps merged (restored from the map file)" : "maps merged") +
                             ": KeyFrame " + std::to_string(m.current_kf_id) + " (robot " +
                             std::to_string(robot_of_keyframe(m.current_kf_id)) + ") <-> KeyFrame " +
                             std::to_string(m.loop_kf_id) + " (robot " + std::to_string(robot_of_keyframe(m.loop_kf_id)) +
                             "), " + std::to_string(m.matches) + " matches";
    log_info(line);
    EventRow e = row(restored ? "merge_restored" : "merge", data_now);
    e.seq = m.current_kf_id;
    e.detail = line;
    recorder_.event(std::move(e));
  }
  merges_announced_ = merges.size();
  return fresh;
}

bool EdgeSystem::save_map(const std::string& path, std::string* message) {
  std::string error;
  const bool ok = durability_.save(path, clock_(), &error);
  const std::string target = path.empty() ? durability_.params().checkpoint_file : path;
  *message = ok ? "Global-Map saved to " + target : error;
  return ok;
}

bool EdgeSystem::load_map(const std::string& path, std::string* message) {
  try {
    durability_.load(path);
  } catch (const std::exception& e) {
    *message = e.what();
    return false;
  }
  rebase_announcements();
  const std::string source = path.empty() ? durability_.params().checkpoint_file : path;
  *message = "Global-Map loaded from " + source + ": " + std::to_string(session_->global_map()->num_keyframes()) +
             " KeyFrames";
  log_warn(*message);
  return true;
}

namespace {
EdgeCounters total_counters(const EdgeSession& session) {
  EdgeCounters t = session.counters(0);
  for (int r = 1; r < session.robots(); ++r) {
    const EdgeCounters c = session.counters(r);
    t.received += c.received;
    t.inserted += c.inserted;
    t.duplicates += c.duplicates;
    t.late_keyframes += c.late_keyframes;
    t.rejected_condition1 += c.rejected_condition1;
    t.rejected_condition2 += c.rejected_condition2;
    t.invalid += c.invalid;
    t.foreign_ids += c.foreign_ids;
    t.resets += c.resets;
    t.updates_built += c.updates_built;
    t.relocalization_updates_built += c.relocalization_updates_built;
    t.updates_on_divergence += c.updates_on_divergence;
  }
  return t;  // the seqs are robot 0's: each robot has its own (ack)
}
// Where the robot's KeyFrames went (module/edge_session.h KeyFrameAccount): distinct ids
// received, inserted, still in the Global-Map, culled; `lost` = inserted but neither (a bug).
MetricsJson account_json(const KeyFrameAccount& a) {
  size_t lost = 0;
  for (uint32_t id : a.inserted)
    if (!std::binary_search(a.in_map.begin(), a.in_map.end(), id) &&
        !std::binary_search(a.culled.begin(), a.culled.end(), id))
      ++lost;
  MetricsJson j;
  j.integer("received", static_cast<long long>(a.received.size()))
      .integer("inserted", static_cast<long long>(a.inserted.size()))
      .integer("in_map", static_cast<long long>(a.in_map.size()))
      .integer("culled", static_cast<long long>(a.culled.size()))
      .integer("lost", static_cast<long long>(lost));
  return j;
}
std::string pose_json(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  const Eigen::Vector3d t = T.translation();
  std::ostringstream o;
  o.precision(9);
  o << "[" << t.x() << ", " << t.y() << ", " << t.z() << ", " << q.x() << ", " << q.y() << ", " << q.z() << ", "
    << q.w() << "]";
  return o.str();
}
}  // namespace

Figures EdgeSystem::stats() const {
  const EdgeCounters c = total_counters(*session_);
  const auto map = session_->global_map();
  Figures f;
  f.add("keyframes_received", static_cast<double>(c.received))
      .add("keyframes_inserted", static_cast<double>(c.inserted))
      .add("keyframes_duplicate", static_cast<double>(c.duplicates))
      .add("keyframes_late", static_cast<double>(c.late_keyframes))
      .add("keyframes_rejected_condition1", static_cast<double>(c.rejected_condition1))
      .add("keyframes_rejected_condition2", static_cast<double>(c.rejected_condition2))
      .add("messages_invalid", static_cast<double>(c.invalid + malformed()))
      .add("keyframes_malformed", static_cast<double>(malformed(Topic::kKeyFrames)))
      .add("frames_malformed", static_cast<double>(malformed(Topic::kFrames)))
      .add("resets", static_cast<double>(c.resets))
      .add("global_map_keyframes", static_cast<double>(map->num_keyframes()))
      .add("global_map_points", static_cast<double>(map->num_map_points()))
      .add("loops_closed", static_cast<double>(session_->loops().size()))
      .add("maps_merged", static_cast<double>(session_->merges().size()))
      .add("keyframes_foreign_ids", static_cast<double>(c.foreign_ids))
      .add("mapping_idle", session_->mapping_idle() ? 1.0 : 0.0)
      .add("keyframe_received_seq", static_cast<double>(c.received_seq))
      .add("keyframe_durable_seq", static_cast<double>(durability_.durable_seq()))
      .add("checkpoints", static_cast<double>(durability_.checkpoints()));
  std::lock_guard<std::mutex> lock(figures_mutex_);
  f.add("updates_sent", static_cast<double>(updates_sent_))
      .add("update_bytes_sent", static_cast<double>(update_bytes_))
      .add("keyframe_bytes_received", static_cast<double>(keyframe_bytes_))
      .add("keyframe_latency_ms_last", keyframe_latency_ms_.empty() ? 0.0 : keyframe_latency_ms_.back())
      .add("update_build_ms_last", update_build_ms_.empty() ? 0.0 : update_build_ms_.back());
  return f;
}

// The Global-Map's KeyFrames in the world frame (several robots): those of a map not yet
// joined with robot 0's stay in their own coordinates (the run's metrics say which: map_group).
EdgeKeyFrames EdgeSystem::world_keyframes() const {
  EdgeKeyFrames k = session_->keyframe_poses();
  if (robots() == 1) return k;
  for (KeyFramePose& p : k.in_map)
    if (const auto T = session_->frames().T_world_group(session_->frames().group_of(p.id))) p.T_wc = *T * p.T_wc;
  return k;
}

void EdgeSystem::sample_memory() {
  {
    std::lock_guard<std::mutex> lock(write_mutex_);
    if (!heap_clock_.due(clock_())) return;
  }
  const HeapUsage h = read_heap_usage();
  if (!h.supported) return;
  EventRow e = row("heap", -1);
  e.bytes = h.in_use_bytes;
  const auto map = session_->global_map();
  e.detail = memory_row_detail(h, "global_map", map->num_keyframes(), map->num_map_points());
  // After the reading, so the row shows what the allocator had kept since the last release.
  if (settings_.session.release_free_heap) {
    const HeapRelease released = release_free_heap_pages();
    e.detail += " release_ms=" + std::to_string(released.ms);
  }
  recorder_.event(std::move(e));
}

void EdgeSystem::write_outputs() {
  sample_memory();
  recorder_.flush();
  if (!recorder_.writes_metrics() && !recorder_.writes_keyframes()) return;
  std::lock_guard<std::mutex> write_lock(write_mutex_);
  const EdgeCounters c = total_counters(*session_);
  MetricsJson keyframes, m;
  keyframes.integer("received", static_cast<long long>(c.received))
      .integer("inserted", static_cast<long long>(c.inserted))
      .integer("duplicates", static_cast<long long>(c.duplicates))
      .integer("rejected_condition1", static_cast<long long>(c.rejected_condition1))
      .integer("rejected_condition2", static_cast<long long>(c.rejected_condition2))
      .integer("invalid", static_cast<long long>(c.invalid + malformed()))
      .integer("resets", static_cast<long long>(c.resets))
      .integer("foreign_ids", static_cast<long long>(c.foreign_ids));
  const auto map = session_->global_map();
  m.text("node", "edge")
      .object("keyframes", keyframes)
      .integer("global_map_keyframes", static_cast<long long>(map->num_keyframes()))
      .integer("global_map_points", static_cast<long long>(map->num_map_points()))
      .object("malformed_keyframes", counts_by_kind(malformed_keyframes_.counter()))
      .object("malformed_frames", counts_by_kind(malformed_frames_.counter()));
  add_module_figures(m, session_->module_figures());
  if (robots() > 1) {
    // Per robot: its deliveries and where its map is (T_world_robot: x y z qx qy qz qw, or null
    // before its map joined robot 0's); and every merge with its transform.
    MetricsJson per_robot;
    for (int r = 0; r < robots(); ++r) {
      const EdgeCounters rc = session_->counters(r);
      const RobotPlacement p = session_->placement(r);
      MetricsJson one;
      one.integer("keyframes_received", static_cast<long long>(rc.received))
          .integer("keyframes_inserted", static_cast<long long>(rc.inserted))
          .integer("keyframes_invalid", static_cast<long long>(rc.invalid))
          .integer("foreign_ids", static_cast<long long>(rc.foreign_ids))
          .integer("updates_built", static_cast<long long>(rc.updates_built))
          .integer("map_group", p.group)
          .object("keyframe_account", account_json(session_->keyframe_account(r)))
          .raw("T_world_robot", p.T_world_robot ? pose_json(*p.T_world_robot) : "null");
      {
        std::lock_guard<std::mutex> lock(figures_mutex_);
        one.timing("update_latency_ms", update_latency_by_robot_[r]).timing("keyframe_transmit_ms", keyframe_latency_by_robot_[r]);
      }
      per_robot.object(std::to_string(r), one);
    }
    m.object("robots", per_robot);
    std::string merges = "[";
    for (const MergeEvent& e : session_->merges()) {
      if (merges.size() > 1) merges += ", ";
      merges += "{\"keyframe\": " + std::to_string(e.current_kf_id) + ", \"loop_keyframe\": " +
                std::to_string(e.loop_kf_id) + ", \"robot\": " + std::to_string(robot_of_keyframe(e.current_kf_id)) +
                ", \"loop_robot\": " + std::to_string(robot_of_keyframe(e.loop_kf_id)) + ", \"matches\": " +
                std::to_string(e.matches) + ", \"T_into_from\": " + pose_json(e.T_into_from) + "}";
    }
    m.raw("merges", merges + "]");
  }
  {
    std::lock_guard<std::mutex> lock(figures_mutex_);
    m.integer("updates_sent", static_cast<long long>(updates_sent_))
        .integer("updates_on_divergence", static_cast<long long>(c.updates_on_divergence))
        .integer("update_bytes_sent", static_cast<long long>(update_bytes_))
        .integer("keyframe_bytes_received", static_cast<long long>(keyframe_bytes_))
        .timing("keyframe_transmit_ms", keyframe_latency_ms_)
        .timing("update_build_ms", update_build_ms_)
        // After each KeyFrame Local-Mapping finished: the largest distance between a KeyFrame
        // the mobile made since its last update and the edge's (EdgeSession::mobile_divergence_m).
        .timing("mobile_divergence_cm", divergence_cm_);
  }
  try {
    recorder_.metrics(m);
    if (recorder_.writes_keyframes()) recorder_.keyframes(world_keyframes());
  } catch (const std::exception& e) {
    if (write_error_log_.allow(clock_())) log_error(e.what());
  }
}

}  // namespace edge_slam
