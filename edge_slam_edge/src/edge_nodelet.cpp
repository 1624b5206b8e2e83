// The Edge-SLAM edge nodelet: ROS plumbing around edge_slam::EdgeSession.
//   in:  keyframes (always taken; conditions 1-2 decide insertion), frames (relocalization),
//        keyframe_floor (std_msgs/UInt64: seqs the mobile will never send again)
//   out: map_updates (Local-Map Update Module timer; relocalization answers), keyframe_acks
//        (5 Hz: received / durable KeyFrame seqs and the boot id), ~global_map
//        (PointCloud2), ~keyframes (MarkerArray), ~keyframe_path (nav_msgs/Path), ~loops
//        (one line per loop closed), ~stats (1 Hz)
//   srv: ~status (edge_slam_msgs/GetEdgeStatus: counters and KeyFrame id accounting),
//        ~save_map, ~load_map (edge_slam_msgs/MapFile; an empty path means ~checkpoint_file)
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame,
// ~stats_csv, ~metrics_file, ~keyframes_file (the Global-Map's KeyFrame poses; empty = not written),
// ~checkpoint_file (empty = no persistence), ~restore_on_start (true); the checkpoint period is
// delivery/checkpoint_period in the slam config.
// Malformed messages (bytes that do not decode, checked before anything is allocated, or
// fields that break the record rules) are rejected, counted per topic and per reason
// (~status malformed_keyframes / malformed_frames, ~stats keyframes_malformed /
// frames_malformed; per kind of problem in metrics.json) and logged once per kind of problem,
// then throttled; nothing crashes.
#include <edge_slam/io/event_log.h>
#include <edge_slam/io/metrics_json.h>
#include <edge_slam/io/output_path.h>
#include <edge_slam/io/trajectory_io.h>
#include <edge_slam/module/edge_session.h>
#include <edge_slam/module/tracking_params.h>
#include <edge_slam/util/rejection_counter.h>
#include <edge_slam/util/wall_clock.h>
#include <edge_slam_bridge/checked_deserialization.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/message_conversion.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <edge_slam_bridge/raw_message.h>
#include <edge_slam_msgs/GetEdgeStatus.h>
#include <edge_slam_msgs/KeyFrameAck.h>
#include <edge_slam_msgs/MapFile.h>
#include <edge_slam_msgs/Stats.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt64.h>
#include <sys/stat.h>

#include <atomic>
#include <cstdio>
#include <random>
#include <memory>
#include <mutex>
#include <sstream>

namespace edge_slam_edge {

template <typename M>
size_t wire_size(const M& msg) {
  return ros::serialization::serializationLength(msg);
}

class EdgeNodelet : public nodelet::Nodelet {
 public:
  ~EdgeNodelet() override {
    checkpoint_timer_.stop();
    checkpoint("shutdown");
    write_metrics();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getMTNodeHandle();
    ros::NodeHandle& pnh = getMTPrivateNodeHandle();
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("metrics_file", metrics_file_, "");
    pnh.param<std::string>("keyframes_file", keyframes_file_, "");
    pnh.param<std::string>("checkpoint_file", checkpoint_file_, "");
    bool restore_on_start = true;
    pnh.param("restore_on_start", restore_on_start, true);
    double checkpoint_period = 5.0;
    std::string stats_csv;
    pnh.param<std::string>("stats_csv", stats_csv, "");
    double update_period = 5.0;
    try {
      const edge_slam::NodeConfig cfg = edge_slam::load_node_config(pnh);
      const edge_slam::OrbParams orb = edge_slam::load_orb_params(cfg.slam);
      const edge_slam::EdgeSessionParams params = edge_slam::load_edge_session_params(cfg.slam);
      update_period = params.update_period;
      checkpoint_period = cfg.slam.get_double_or("delivery/checkpoint_period", 5.0, 0.5, 3600.0);
      events_ = std::make_unique<edge_slam::EventLog>(stats_csv);
      session_ = std::make_unique<edge_slam::EdgeSession>(cfg.camera, orb.num_levels, orb.scale_factor,
                                                          cfg.vocabulary, params);
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start the edge: %s", e.what());
      return;
    }
    boot_id_ = new_boot_id();
    if (!checkpoint_file_.empty() && restore_on_start) restore_checkpoint();
    update_pub_ = nh.advertise<edge_slam_msgs::MapUpdate>("map_updates", 10);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("global_map", 1, true);
    marker_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true);
    path_pub_ = pnh.advertise<nav_msgs::Path>("keyframe_path", 1, true);
    loop_pub_ = pnh.advertise<std_msgs::String>("loops", 10, true);
    stats_pub_ = pnh.advertise<edge_slam_msgs::Stats>("stats", 10);
    status_srv_ = pnh.advertiseService("status", &EdgeNodelet::on_status, this);
    save_srv_ = pnh.advertiseService("save_map", &EdgeNodelet::on_save_map, this);
    load_srv_ = pnh.advertiseService("load_map", &EdgeNodelet::on_load_map, this);
    ack_pub_ = nh.advertise<edge_slam_msgs::KeyFrameAck>("keyframe_acks", 10);
    floor_sub_ = nh.subscribe("keyframe_floor", 10, &EdgeNodelet::on_floor, this);
    keyframe_sub_ = nh.subscribe("keyframes", 1000, &EdgeNodelet::on_keyframe_bytes, this);
    frame_sub_ = nh.subscribe("frames", 5, &EdgeNodelet::on_frame_bytes, this);
    update_timer_ = nh.createTimer(ros::Duration(update_period), [this](const ros::TimerEvent&) { send_update(); });
    display_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_map(); });
    stats_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_stats(); });
    // Acknowledgements at a steady 5 Hz: cheap, and a mobile that reconnects learns the state at once.
    ack_timer_ = nh.createWallTimer(ros::WallDuration(0.2), [this](const ros::WallTimerEvent&) { publish_ack(); });
    progress_timer_ = nh.createWallTimer(ros::WallDuration(0.01),
                                         [this](const ros::WallTimerEvent&) { publish_ack_on_progress(); });
    if (!checkpoint_file_.empty())
      checkpoint_timer_ = nh.createWallTimer(ros::WallDuration(checkpoint_period),
                                             [this](const ros::WallTimerEvent&) { checkpoint("periodic"); });
    NODELET_INFO("edge ready: Local-Mapping + Loop-Closing on the Global-Map, updates every %.1f s", update_period);
  }

  // Bytes first: a corrupt array length must not reach roscpp's own (unchecked) deserializer.
  void on_keyframe_bytes(const boost::shared_ptr<const edge_slam::RawMessage<edge_slam_msgs::KeyFrame>>& raw) {
    auto msg = boost::make_shared<edge_slam_msgs::KeyFrame>();
    const edge_slam::DecodeStatus status = edge_slam::deserialize_checked(raw->bytes.data(), raw->bytes.size(), *msg);
    if (!status.ok) return reject(malformed_keyframes_, "keyframe", status.error, raw->bytes.size());
    on_keyframe(msg);
  }

  void on_frame_bytes(const boost::shared_ptr<const edge_slam::RawMessage<edge_slam_msgs::Frame>>& raw) {
    auto msg = boost::make_shared<edge_slam_msgs::Frame>();
    const edge_slam::DecodeStatus status = edge_slam::deserialize_checked(raw->bytes.data(), raw->bytes.size(), *msg);
    if (!status.ok) return reject(malformed_frames_, "frame", status.error, raw->bytes.size());
    on_frame(msg);
  }

  // Counted per topic and reason; each kind of problem logged the first time, then throttled.
  void reject(edge_slam::RejectionCounter& counter, const char* topic, const std::string& why, size_t bytes) {
    const uint64_t same_kind = counter.add(why);
    if (same_kind == 1)
      NODELET_ERROR("rejecting a malformed message on '%ss' (first of its kind): %s", topic, why.c_str());
    else
      NODELET_ERROR_THROTTLE(5.0, "rejecting a malformed message on '%ss' (%lu so far, %lu like this): %s", topic,
                             static_cast<unsigned long>(counter.total()), static_cast<unsigned long>(same_kind),
                             why.c_str());
    log_event(topic, -1, 0, bytes, -1, -1, "malformed");
  }

  void on_keyframe(const edge_slam_msgs::KeyFrame::ConstPtr& msg) {
    const size_t bytes = wire_size(*msg);
    edge_slam::KeyFrameRecord record;
    const edge_slam::DecodeStatus status = edge_slam::from_message(*msg, record);
    if (!status.ok) return reject(malformed_keyframes_, "keyframe", status.error, bytes);
    // Created on the mobile (its wall clock) -> received and deserialised here.
    const double latency_ms = (edge_slam::wall_clock_seconds() - record.created_wall) * 1e3;
    {
      std::lock_guard<std::mutex> lock(figures_mutex_);
      keyframe_latency_ms_.push_back(latency_ms);
      keyframe_bytes_ += bytes;
    }
    std::string error;
    const edge_slam::KeyFrameVerdict v = session_->receive_keyframe(record, edge_slam::wall_clock_seconds(), &error);
    log_event("keyframe", record.stamp, record.seq, bytes, latency_ms, -1, edge_slam::to_string(v));
    if (v == edge_slam::KeyFrameVerdict::kInvalid)
      NODELET_ERROR_THROTTLE(5.0, "KeyFrame %u refused: %s", record.id, error.c_str());
    else if (v == edge_slam::KeyFrameVerdict::kReset)
      NODELET_WARN("reset requested by the mobile (KeyFrame %u): Global-Map cleared", record.id);
    else
      NODELET_DEBUG("KeyFrame %u: %s", record.id, edge_slam::to_string(v));
  }

  static uint64_t new_boot_id() {
    std::random_device rd;
    return (static_cast<uint64_t>(rd()) << 32) ^ rd() ^ static_cast<uint64_t>(edge_slam::wall_clock_seconds() * 1e6);
  }

  void on_floor(const std_msgs::UInt64::ConstPtr& msg) { session_->skip_keyframes_through(msg->data); }

  void publish_ack() {
    edge_slam_msgs::KeyFrameAck ack;
    ack.boot_id = boot_id_;
    ack.received_seq = session_->counters().received_seq;
    ack.persistent = !checkpoint_file_.empty();
    ack.durable_seq = durable_seq_;
    ack.mapped_seq = session_->mapped_seq();
    last_acked_mapped_seq_ = ack.mapped_seq;
    ack_pub_.publish(ack);
  }

  // As soon as Local-Mapping is done with a KeyFrame the mobile hears of it: its condition 2
  // waits for that (edge_slam/mobile_keyframe_pacing), like ORB-SLAM2's tracker reading its mapper.
  void publish_ack_on_progress() {
    if (session_->mapped_seq() != last_acked_mapped_seq_) publish_ack();
  }

  // A restored Global-Map is durable by definition (it came from the file). A corrupt or
  // unreadable file: one clear error, the file kept aside for inspection, and an empty start.
  void restore_checkpoint() {
    struct stat st;
    if (::stat(checkpoint_file_.c_str(), &st) != 0) {
      NODELET_INFO("no checkpoint at %s yet: starting with an empty Global-Map", checkpoint_file_.c_str());
      return;
    }
    try {
      session_->load_map(checkpoint_file_);
      durable_seq_ = session_->counters().received_seq;
      NODELET_INFO("restored the Global-Map from %s: %zu KeyFrames, KeyFrame seqs up to %lu", checkpoint_file_.c_str(),
                   session_->global_map()->num_keyframes(), static_cast<unsigned long>(durable_seq_.load()));
    } catch (const std::exception& e) {
      const std::string aside =
          checkpoint_file_ + ".corrupt-" + std::to_string(static_cast<long long>(edge_slam::wall_clock_seconds()));
      const bool moved = std::rename(checkpoint_file_.c_str(), aside.c_str()) == 0;
      NODELET_ERROR("cannot restore the checkpoint (%s): starting with an empty Global-Map; the file %s", e.what(),
                    moved ? ("was renamed " + aside).c_str() : "could not be renamed and will be overwritten");
    }
  }

  // The session snapshots under its locks and writes outside them; `checkpointing_` only keeps
  // two writers (timer, service, shutdown) from racing for the same temporary file.
  bool checkpoint(const char* why, std::string* error = nullptr) {
    if (!session_ || checkpoint_file_.empty()) return false;
    if (checkpointing_.exchange(true)) return false;
    bool ok = true;
    try {
      const uint64_t durable = session_->save_map(checkpoint_file_);
      if (durable > durable_seq_) durable_seq_ = durable;
      ++checkpoints_;
      NODELET_DEBUG("%s checkpoint: KeyFrame seqs up to %lu durable", why, static_cast<unsigned long>(durable));
    } catch (const std::exception& e) {
      ok = false;
      if (error) *error = e.what();
      NODELET_ERROR_THROTTLE(30.0, "%s checkpoint failed: %s", why, e.what());
    }
    checkpointing_ = false;
    return ok;
  }

  bool on_save_map(edge_slam_msgs::MapFile::Request& req, edge_slam_msgs::MapFile::Response& res) {
    const std::string path = req.path.empty() ? checkpoint_file_ : req.path;
    if (path.empty()) {
      res.ok = false;
      res.message = "no path given and no ~checkpoint_file set";
      return true;
    }
    std::string error;
    if (path == checkpoint_file_) {
      res.ok = checkpoint("requested", &error);
      if (!res.ok && error.empty()) error = "a checkpoint is being written right now; try again";
    } else {
      try {
        session_->save_map(path);
        res.ok = true;
      } catch (const std::exception& e) {
        error = e.what();
      }
    }
    res.message = res.ok ? "Global-Map saved to " + path : error;
    return true;
  }

  // A loaded map is a new session for the mobile (new boot id): it resends all it holds beyond
  // what the map says was received; until the next checkpoint nothing more is durable.
  bool on_load_map(edge_slam_msgs::MapFile::Request& req, edge_slam_msgs::MapFile::Response& res) {
    const std::string path = req.path.empty() ? checkpoint_file_ : req.path;
    try {
      if (path.empty()) throw std::runtime_error("no path given and no ~checkpoint_file set");
      session_->load_map(path);
      durable_seq_ = path == checkpoint_file_ ? session_->counters().received_seq : 0;
      boot_id_ = new_boot_id();
      res.ok = true;
      res.message = "Global-Map loaded from " + path + ": " +
                    std::to_string(session_->global_map()->num_keyframes()) + " KeyFrames";
      NODELET_WARN("%s", res.message.c_str());
    } catch (const std::exception& e) {
      res.ok = false;
      res.message = e.what();
    }
    return true;
  }

  void on_frame(const edge_slam_msgs::Frame::ConstPtr& msg) {
    const size_t bytes = wire_size(*msg);
    edge_slam::FrameRecord record;
    const edge_slam::DecodeStatus status = edge_slam::from_message(*msg, record);
    if (!status.ok) return reject(malformed_frames_, "frame", status.error, bytes);
    const double latency_ms = (edge_slam::wall_clock_seconds() - record.created_wall) * 1e3;
    const double start = edge_slam::wall_clock_seconds();
    std::string error;
    auto update = session_->build_relocalization_update(record, start, &error);
    if (!error.empty()) NODELET_ERROR_THROTTLE(5.0, "Frame %u refused: %s", record.id, error.c_str());
    log_event("frame", record.stamp, record.seq, bytes, latency_ms, -1,
              update ? "answered" : (error.empty() ? "no candidates" : "refused"));
    if (update) publish(*update);
  }

  void send_update() {
    if (auto update = session_->build_local_map_update(edge_slam::wall_clock_seconds())) publish(*update);
  }

  // Construction latency = build start -> serialised and handed to ROS.
  void publish(edge_slam::MapUpdateRecord& update) {
    update.publish_stamp = edge_slam::wall_clock_seconds();
    const edge_slam_msgs::MapUpdate msg = edge_slam::to_message(update);
    const size_t bytes = wire_size(msg);
    update_pub_.publish(msg);
    const double build_ms = (edge_slam::wall_clock_seconds() - update.build_start) * 1e3;
    {
      std::lock_guard<std::mutex> lock(figures_mutex_);
      update_build_ms_.push_back(build_ms);
      update_bytes_ += bytes;
      ++updates_sent_;
    }
    const bool reloc = update.kind == edge_slam::MapUpdateKind::kRelocalization;
    log_event("update_sent", ros::Time::now().toSec(), update.seq, bytes, -1, build_ms,
              std::string(reloc ? "relocalization " : "periodic ") + std::to_string(update.keyframes.size()) + " KFs " +
                  std::to_string(update.points.size()) + " points");
  }

  bool on_status(edge_slam_msgs::GetEdgeStatus::Request&, edge_slam_msgs::GetEdgeStatus::Response& res) {
    const edge_slam::EdgeCounters c = session_->counters();
    res.received = static_cast<uint32_t>(c.received);
    res.inserted = static_cast<uint32_t>(c.inserted);
    res.duplicates = static_cast<uint32_t>(c.duplicates);
    res.rejected_condition1 = static_cast<uint32_t>(c.rejected_condition1);
    res.rejected_condition2 = static_cast<uint32_t>(c.rejected_condition2);
    res.invalid = static_cast<uint32_t>(c.invalid + malformed());
    res.malformed_keyframes = static_cast<uint32_t>(malformed_keyframes_.total());
    res.malformed_frames = static_cast<uint32_t>(malformed_frames_.total());
    res.resets = static_cast<uint32_t>(c.resets);
    res.updates_sent = static_cast<uint32_t>(c.updates_built);
    res.relocalization_updates_sent = static_cast<uint32_t>(c.relocalization_updates_built);
    res.loops_closed = static_cast<uint32_t>(session_->loops_closed());
    const auto map = session_->global_map();
    res.global_map_keyframes = static_cast<uint32_t>(map->num_keyframes());
    res.global_map_points = static_cast<uint32_t>(map->num_map_points());
    const edge_slam::KeyFrameAccount a = session_->keyframe_account();
    res.inserted_ids = a.inserted;
    res.culled_ids = a.culled;
    res.global_map_ids = a.in_map;
    res.received_ids = a.received;
    res.received_seq = c.received_seq;
    res.durable_seq = durable_seq_;
    res.boot_id = boot_id_;
    res.checkpoints = static_cast<uint32_t>(checkpoints_);
    return true;
  }

  void log_event(const char* event, double data_time, uint64_t seq, size_t bytes, double latency_ms,
                 double duration_ms, const std::string& detail) {
    events_->add(event, data_time, seq, bytes, latency_ms, duration_ms,
                 static_cast<long>(session_->global_map()->num_keyframes()), detail);
  }

  void publish_map() {
    if (!session_) return;
    const auto map = session_->global_map();
    const ros::Time stamp = ros::Time::now();
    if (cloud_pub_.getNumSubscribers() > 0)
      cloud_pub_.publish(edge_slam::to_point_cloud(map->map_points(), map_frame_, stamp));
    const auto kfs = map->keyframes();
    if (marker_pub_.getNumSubscribers() > 0)
      marker_pub_.publish(edge_slam::keyframe_markers(kfs, map_frame_, stamp, "global_map", 1.0f, 0.55f, 0.0f));
    nav_msgs::Path path;
    path.header.frame_id = map_frame_;
    path.header.stamp = stamp;
    for (const auto& kf : kfs) {
      geometry_msgs::PoseStamped p;
      p.header.frame_id = map_frame_;
      p.header.stamp = ros::Time(kf->stamp());
      p.pose = edge_slam::pose_to_message(kf->T_wc());
      path.poses.push_back(p);
    }
    path_pub_.publish(path);
  }

  void publish_stats() {
    if (!session_) return;
    const auto loops = session_->loops();
    for (size_t i = loops_announced_; i < loops.size(); ++i) {
      std_msgs::String s;
      s.data = "loop closed: KeyFrame " + std::to_string(loops[i].current_kf_id) + " <-> KeyFrame " +
               std::to_string(loops[i].loop_kf_id) + " (" + std::to_string(loops[i].matches) + " matches)";
      NODELET_INFO("%s", s.data.c_str());
      loop_pub_.publish(s);
      log_event("loop", ros::Time::now().toSec(), loops[i].current_kf_id, 0, -1, -1, s.data);
    }
    loops_announced_ = loops.size();

    const edge_slam::EdgeCounters c = session_->counters();
    const auto map = session_->global_map();
    edge_slam_msgs::Stats m;
    m.header.stamp = ros::Time::now();
    m.node = "edge";
    auto add = [&m](const char* name, double v) {
      m.names.push_back(name);
      m.values.push_back(v);
    };
    add("keyframes_received", static_cast<double>(c.received));
    add("keyframes_inserted", static_cast<double>(c.inserted));
    add("keyframes_duplicate", static_cast<double>(c.duplicates));
    add("keyframes_late", static_cast<double>(c.late_keyframes));
    add("keyframes_rejected_condition1", static_cast<double>(c.rejected_condition1));
    add("keyframes_rejected_condition2", static_cast<double>(c.rejected_condition2));
    add("messages_invalid", static_cast<double>(c.invalid + malformed()));
    add("keyframes_malformed", static_cast<double>(malformed_keyframes_.total()));
    add("frames_malformed", static_cast<double>(malformed_frames_.total()));
    add("resets", static_cast<double>(c.resets));
    add("global_map_keyframes", static_cast<double>(map->num_keyframes()));
    add("global_map_points", static_cast<double>(map->num_map_points()));
    add("loops_closed", static_cast<double>(loops.size()));
    add("mapping_idle", session_->mapping_idle() ? 1.0 : 0.0);
    add("keyframe_received_seq", static_cast<double>(c.received_seq));
    add("keyframe_durable_seq", static_cast<double>(durable_seq_));
    add("checkpoints", static_cast<double>(checkpoints_));
    {
      std::lock_guard<std::mutex> lock(figures_mutex_);
      add("updates_sent", static_cast<double>(updates_sent_));
      add("update_bytes_sent", static_cast<double>(update_bytes_));
      add("keyframe_bytes_received", static_cast<double>(keyframe_bytes_));
      add("keyframe_latency_ms_last", keyframe_latency_ms_.empty() ? 0.0 : keyframe_latency_ms_.back());
      add("update_build_ms_last", update_build_ms_.empty() ? 0.0 : update_build_ms_.back());
    }
    stats_pub_.publish(m);
    events_->flush();
    write_metrics();
  }

  // metrics.json, rewritten every second and at shutdown.
  void write_metrics() {
    if (!session_ || (metrics_file_.empty() && keyframes_file_.empty())) return;
    std::lock_guard<std::mutex> write_lock(write_mutex_);
    const edge_slam::EdgeCounters c = session_->counters();
    edge_slam::MetricsJson keyframes, m;
    keyframes.integer("received", static_cast<long long>(c.received))
        .integer("inserted", static_cast<long long>(c.inserted))
        .integer("duplicates", static_cast<long long>(c.duplicates))
        .integer("rejected_condition1", static_cast<long long>(c.rejected_condition1))
        .integer("rejected_condition2", static_cast<long long>(c.rejected_condition2))
        .integer("invalid", static_cast<long long>(c.invalid + malformed()))
        .integer("resets", static_cast<long long>(c.resets));
    const auto map = session_->global_map();
    m.text("node", "edge")
        .object("keyframes", keyframes)
        .integer("global_map_keyframes", static_cast<long long>(map->num_keyframes()))
        .integer("global_map_points", static_cast<long long>(map->num_map_points()))
        .object("malformed_keyframes", by_kind(malformed_keyframes_))
        .object("malformed_frames", by_kind(malformed_frames_));
    edge_slam::add_module_figures(m, session_->module_figures());
    {
      std::lock_guard<std::mutex> lock(figures_mutex_);
      m.integer("updates_sent", static_cast<long long>(updates_sent_))
          .integer("update_bytes_sent", static_cast<long long>(update_bytes_))
          .integer("keyframe_bytes_received", static_cast<long long>(keyframe_bytes_))
          .timing("keyframe_transmit_ms", keyframe_latency_ms_)
          .timing("update_build_ms", update_build_ms_);
    }
    try {
      if (!metrics_file_.empty()) m.write(metrics_file_);
      if (!keyframes_file_.empty()) write_keyframes(*map);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(30.0, "%s", e.what());
    }
  }

  // "id stamp tx ty tz qx qy qz qw" (T_wc) of every Global-Map KeyFrame, replaced atomically.
  void write_keyframes(const edge_slam::Map& map) {
    std::ostringstream out;
    out << "# keyframe_id timestamp tx ty tz qx qy qz qw (T_wc, Global-Map)\n";
    for (const auto& kf : map.keyframes()) {
      out << kf->id() << ' ';
      edge_slam::write_tum_pose(out, kf->stamp(), kf->T_wc());
    }
    edge_slam::write_file_atomically(keyframes_file_, out.str());
  }


  std::unique_ptr<edge_slam::EdgeSession> session_;
  std::unique_ptr<edge_slam::EventLog> events_;
  std::string map_frame_, metrics_file_, keyframes_file_, checkpoint_file_;
  std::atomic<uint64_t> boot_id_{0}, durable_seq_{0}, checkpoints_{0};
  std::atomic<bool> checkpointing_{false};
  static edge_slam::MetricsJson by_kind(const edge_slam::RejectionCounter& c) {  // reason kind -> count
    edge_slam::MetricsJson j;
    for (const auto& [kind, n] : c.by_kind()) j.integer(kind, static_cast<long long>(n));
    return j;
  }
  uint64_t malformed() const { return malformed_keyframes_.total() + malformed_frames_.total(); }
  edge_slam::RejectionCounter malformed_keyframes_, malformed_frames_;
  size_t loops_announced_ = 0;  // stats timer only
  std::mutex write_mutex_;      // metrics.json writers (timer, destructor)
  std::mutex figures_mutex_;    // the figures below: message callbacks vs timers
  std::vector<double> keyframe_latency_ms_, update_build_ms_;
  uint64_t keyframe_bytes_ = 0, update_bytes_ = 0, updates_sent_ = 0;
  ros::Publisher ack_pub_, update_pub_, cloud_pub_, marker_pub_, path_pub_, loop_pub_, stats_pub_;
  ros::Subscriber keyframe_sub_, frame_sub_, floor_sub_;
  ros::ServiceServer status_srv_, save_srv_, load_srv_;
  ros::Timer update_timer_;
  ros::WallTimer display_timer_, stats_timer_, ack_timer_, progress_timer_, checkpoint_timer_;
  std::atomic<uint64_t> last_acked_mapped_seq_{0};
};

}  // namespace edge_slam_edge

PLUGINLIB_EXPORT_CLASS(edge_slam_edge::EdgeNodelet, nodelet::Nodelet)
