// The Edge-SLAM mobile nodelet: ROS plumbing around edge_slam::MobileSession.
//   in:  rgb/image + depth/image (image_transport, approximate-time synchronised),
//        rgb/camera_info (intrinsics; YAML when absent), map_updates
//        keyframe_acks (the edge's delivery acknowledgements)
//   out: keyframes (sender thread: first sends and resends), keyframe_floor (std_msgs/UInt64,
//        seqs the edge will never get again), frames (while lost), TF map -> camera, ~odometry, ~path,
//        ~local_map (PointCloud2), ~keyframes (MarkerArray), ~state, ~stats (1 Hz)
//   srv: ~set_map_updates, ~map_update_status (the map-update controller), ~reset,
//        ~delivery_status (KeyFrame delivery counters and the ids created)
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame,
// ~camera_frame, ~use_camera_info (true), ~camera_info_timeout (s), ~stats_csv, ~metrics_file,
// ~trajectory_file (empty = not written), ~path_max_poses, ~image_queue_size (2: a live camera's
// frames are dropped when tracking falls behind; evaluation on a bag sets it deep so every frame
// is tracked, as the monolithic runner does). Bad input is logged once per kind of
// problem (then throttled) with what was expected, counted, and dropped; the nodelet keeps
// running. Counters: malformed map_updates -> rejected_invalid (~map_update_status) and
// updates_rejected_invalid (~stats); camera frames -> images_rejected_{stamp,encoding,size,depth}
// on both; per kind of problem in metrics.json (malformed_updates, camera_frames_dropped).
// Out-of-range parameters are refused at start, naming the parameter and the range.
#include <edge_slam/io/event_log.h>
#include <edge_slam/io/output_path.h>
#include <edge_slam/io/trajectory_io.h>
#include <edge_slam/module/keyframe_delivery.h>
#include <edge_slam/module/mobile_session.h>
#include <edge_slam/module/tracking_params.h>
#include <edge_slam/util/rejection_counter.h>
#include <edge_slam/util/wall_clock.h>
#include <edge_slam_bridge/checked_deserialization.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/message_conversion.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <edge_slam_msgs/GetDeliveryStatus.h>
#include <edge_slam_bridge/raw_message.h>
#include <edge_slam_bridge/ros_param.h>
#include <edge_slam_msgs/GetMapUpdateStatus.h>
#include <edge_slam_msgs/KeyFrameAck.h>
#include <edge_slam_msgs/SetMapUpdates.h>
#include <geometry_msgs/TransformStamped.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt64.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <iomanip>
#include <memory>
#include <mutex>
#include <thread>

#include "camera_info_input.h"
#include "image_input.h"
#include "mobile_metrics.h"

namespace edge_slam_mobile {

using edge_slam::MobileSession;
using SyncPolicy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

template <typename M>
size_t wire_size(const M& msg) {
  return ros::serialization::serializationLength(msg);
}

class MobileNodelet : public nodelet::Nodelet {
 public:
  ~MobileNodelet() override {
    running_ = false;
    if (auto s = session()) s->outbox().close();
    if (sender_.joinable()) sender_.join();
    write_outputs();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getMTNodeHandle();
    ros::NodeHandle& pnh = getMTPrivateNodeHandle();
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("camera_frame", camera_frame_, "camera");
    pnh.param("use_camera_info", use_camera_info_, true);
    pnh.param<std::string>("metrics_file", metrics_file_, "");
    pnh.param<std::string>("dataset", dataset_, "");
    std::string stats_csv, trajectory_file, anchors_file;
    pnh.param<std::string>("stats_csv", stats_csv, "");
    pnh.param<std::string>("trajectory_file", trajectory_file, "");
    pnh.param<std::string>("anchors_file", anchors_file, "");
    try {
      camera_info_timeout_ = edge_slam::param_in_range(pnh, "camera_info_timeout", 2.0, 0.0, 600.0);
      path_max_poses_ = edge_slam::param_in_range(pnh, "path_max_poses", 20000, 1, 10000000);
      image_queue_size_ = edge_slam::param_in_range(pnh, "image_queue_size", 2, 1, 10000);
      config_ = edge_slam::load_node_config(pnh);
      // Parse every section now so a bad value is refused at start, naming the parameter.
      tracking_ = edge_slam::load_tracking_params(config_.slam);  // MobileSession keeps conditions 3-5 only
      orb_ = edge_slam::load_orb_params(config_.slam);
      session_params_ = edge_slam::load_mobile_session_params(config_.slam);
      delivery_ = std::make_unique<edge_slam::KeyFrameDelivery>(edge_slam::load_delivery_params(config_.slam));
      events_ = std::make_unique<edge_slam::EventLog>(stats_csv);
      if (!trajectory_file.empty()) {
        edge_slam::ensure_parent_directory(trajectory_file);
        trajectory_.open(trajectory_file, std::ios::out | std::ios::trunc);
        if (!trajectory_) throw std::runtime_error("cannot create the trajectory file '" + trajectory_file + "'");
        trajectory_ << "# timestamp tx ty tz qx qy qz qw (T_wc of each tracked frame, as tracked on the mobile)\n";
      }
      if (!anchors_file.empty()) {
        edge_slam::ensure_parent_directory(anchors_file);
        anchors_.open(anchors_file, std::ios::out | std::ios::trunc);
        if (!anchors_) throw std::runtime_error("cannot create the anchors file '" + anchors_file + "'");
        anchors_ << "# F <frame stamp> <reference KF id> <T_ref_c: tx ty tz qx qy qz qw>\n"
                 << "# K <KF id> <parent KF id> <T_parent_kf: tx ty tz qx qy qz qw>   (scripts/split_trajectory.py)\n";
      }
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start the mobile: %s", e.what());
      return;
    }

    keyframe_pub_ = nh.advertise<edge_slam_msgs::KeyFrame>("keyframes", 200);
    floor_pub_ = nh.advertise<std_msgs::UInt64>("keyframe_floor", 10);
    ack_sub_ = nh.subscribe("keyframe_acks", 20, &MobileNodelet::on_ack, this);
    delivery_srv_ = pnh.advertiseService("delivery_status", &MobileNodelet::on_delivery_status, this);
    frame_pub_ = nh.advertise<edge_slam_msgs::Frame>("frames", 10);
    odometry_pub_ = pnh.advertise<nav_msgs::Odometry>("odometry", 10);
    path_pub_ = pnh.advertise<nav_msgs::Path>("path", 1, true);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("local_map", 1, true);
    marker_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true);
    state_pub_ = pnh.advertise<std_msgs::String>("state", 10, true);
    stats_pub_ = pnh.advertise<edge_slam_msgs::Stats>("stats", 10);
    update_sub_ = nh.subscribe("map_updates", 5, &MobileNodelet::on_map_update_bytes, this);
    set_srv_ = pnh.advertiseService("set_map_updates", &MobileNodelet::on_set_map_updates, this);
    status_srv_ = pnh.advertiseService("map_update_status", &MobileNodelet::on_status, this);
    reset_srv_ = pnh.advertiseService("reset", &MobileNodelet::on_reset, this);

    // Images and camera_info on the single-threaded handle: frames are tracked one at a time, in
    // order, and the session is created there. Small queues by default: when tracking falls
    // behind, it goes on with the newest frame.
    ros::NodeHandle& st = getNodeHandle();
    it_ = std::make_unique<image_transport::ImageTransport>(st);
    rgb_sub_.subscribe(*it_, "rgb/image", static_cast<uint32_t>(image_queue_size_));
    depth_sub_.subscribe(*it_, "depth/image", static_cast<uint32_t>(image_queue_size_));
    sync_ = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(
        SyncPolicy(static_cast<uint32_t>(std::max(5, image_queue_size_ + 3))), rgb_sub_, depth_sub_);
    sync_->registerCallback(&MobileNodelet::on_rgbd, this);
    if (use_camera_info_) info_sub_ = st.subscribe("rgb/camera_info", 1, &MobileNodelet::on_camera_info, this);
    else start_session(config_.camera, "YAML (use_camera_info is false)");

    display_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_map(); });
    stats_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_stats(); });
    running_ = true;
    sender_ = std::thread([this] { send_keyframes(); });
    NODELET_INFO("mobile ready: Local-Map tracking, KeyFrame conditions 3-5, intrinsics from %s",
                 use_camera_info_ ? "camera_info (YAML if none arrives)" : "YAML");
  }

  std::shared_ptr<MobileSession> session() const { return std::atomic_load(&session_); }

  // Called on the image thread only (or in onInit before any callback).
  void start_session(const edge_slam::PinholeCamera& camera, const std::string& source) {
    try {
      auto s = std::make_shared<MobileSession>(camera, orb_, tracking_, config_.vocabulary, session_params_,
                                               edge_slam::RgbEncoding::kRgb);
      camera_ = camera;
      std::atomic_store(&session_, s);
      NODELET_INFO("tracking with camera '%s' %dx%d fx %.2f fy %.2f cx %.2f cy %.2f from %s", camera.name.c_str(),
                   camera.width, camera.height, camera.fx, camera.fy, camera.cx, camera.cy, source.c_str());
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start tracking: %s", e.what());
    }
  }

  void on_camera_info(const sensor_msgs::CameraInfo::ConstPtr& info) {
    edge_slam::PinholeCamera cam;
    std::string error;
    const bool ok = camera_from_info(*info, config_.camera, cam, error);
    if (session()) {
      if (ok && !same_intrinsics(cam, camera_) && !warned_info_change_) {
        warned_info_change_ = true;
        NODELET_WARN("camera_info changed after tracking started (fx %.2f vs %.2f); keeping the first calibration",
                     cam.fx, camera_.fx);
      }
      return;
    }
    if (!ok) {
      NODELET_ERROR("unusable camera_info (%s): using the YAML calibration", error.c_str());
      start_session(config_.camera, "YAML (camera_info refused)");
      return;
    }
    start_session(cam, "camera_info");
  }

  void on_rgbd(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth) {
    auto s = session();
    if (!s) {
      const ros::WallTime now = ros::WallTime::now();
      if (first_image_wall_.isZero()) first_image_wall_ = now;
      if ((now - first_image_wall_).toSec() < camera_info_timeout_) {
        NODELET_INFO_THROTTLE(5.0, "waiting for rgb/camera_info before tracking (at most %.1f s)", camera_info_timeout_);
        return;
      }
      NODELET_WARN("no camera_info within %.1f s: using the YAML calibration", camera_info_timeout_);
      start_session(config_.camera, "YAML (no camera_info)");
      if (!(s = session())) return;
    }
    ImageCheck check = convert_rgbd(*rgb, *depth, camera_, last_stamp_);
    if (!check.ok) {
      metrics_.on_input_rejected(check.problem);
      const uint64_t same_kind = rejected_frames_.add(check.error);
      if (same_kind == 1) NODELET_ERROR("dropping a camera frame (first of its kind): %s", check.error.c_str());
      else
        NODELET_ERROR_THROTTLE(5.0, "dropping camera frames (%lu dropped so far): %s",
                               static_cast<unsigned long>(rejected_frames_.total()), check.error.c_str());
      return;
    }
    {
      std::lock_guard<std::mutex> lock(output_mutex_);
      last_stamp_ = rgb->header.stamp;
    }
    const double stamp = rgb->header.stamp.toSec();
    const edge_slam::TrackingResult r = s->track(check.rgb, check.depth, stamp);
    if (!r.message.empty() && r.state != edge_slam::TrackingState::kOk)
      NODELET_WARN_THROTTLE(5.0, "tracking: %s", r.message.c_str());
    metrics_.on_frame(r.time_ms);
    log_event("frame", stamp, r.frame_id, 0, -1, r.time_ms, static_cast<long>(s->local_map_keyframes()),
              edge_slam::to_string(r.state));
    if (auto deferred = s->take_deferred_outcome()) report_deferred_update(*s, deferred->first, deferred->second);
    publish_state(r);
    if (r.pose_valid) publish_pose(r.T_cw.inverse(), rgb->header.stamp);
    write_anchors(r, stamp);
    if (auto frame = s->take_relocalization_frame(stamp)) {
      const edge_slam_msgs::Frame msg = edge_slam::to_message(*frame);
      const size_t bytes = wire_size(msg);
      frame_pub_.publish(msg);
      metrics_.on_frame_sent(bytes);
      log_event("frame_sent", stamp, frame->seq, bytes, -1, -1, s->local_map_keyframes(), "");
    }
  }

  // Drains the outbox into the delivery queue (tracking only ever pushes, so network trouble
  // never stalls it), then sends what is due: new records and unacknowledged ones again.
  void send_keyframes() {
    double last_floor = 0;
    while (running_) {
      auto s = session();
      if (!s) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      if (auto record = s->outbox().pop_for(std::chrono::milliseconds(100))) {
        do {
          if (!delivery_->add(std::make_shared<const edge_slam::KeyFrameRecord>(std::move(*record))))
            NODELET_WARN_THROTTLE(5.0, "KeyFrame resend queue full: the oldest unacknowledged record was dropped");
        } while ((record = s->outbox().try_pop()));
      }
      // Nobody listening (edge down): keep them; the edge's next acknowledgement brings them out.
      if (keyframe_pub_.getNumSubscribers() == 0) continue;
      const double now = edge_slam::wall_clock_seconds();
      for (const auto& record : delivery_->take_due(now)) {
        const edge_slam_msgs::KeyFrame msg = edge_slam::to_message(*record);
        const size_t bytes = wire_size(msg);
        keyframe_pub_.publish(msg);
        metrics_.on_keyframe_sent(bytes);
        log_event("keyframe_sent", record->stamp, record->seq, bytes, -1, -1, -1, record->reset ? "reset" : "");
      }
      if (now - last_floor >= 0.2) {
        std_msgs::UInt64 floor;
        floor.data = delivery_->floor();
        floor_pub_.publish(floor);
        last_floor = now;
      }
    }
  }

  void on_ack(const edge_slam_msgs::KeyFrameAck::ConstPtr& msg) {
    edge_slam::KeyFrameAck ack;
    ack.boot_id = msg->boot_id;
    ack.received_seq = msg->received_seq;
    ack.durable_seq = msg->durable_seq;
    ack.persistent = msg->persistent;
    ack.mapped_seq = msg->mapped_seq;
    if (auto s = session()) s->on_edge_progress(msg->mapped_seq);
    const uint64_t restarts = delivery_->counters().edge_restarts;
    delivery_->on_ack(ack, edge_slam::wall_clock_seconds());
    if (delivery_->counters().edge_restarts != restarts)
      NODELET_WARN("the edge restarted (durable up to KeyFrame seq %lu): resending what came after",
                   static_cast<unsigned long>(ack.durable_seq));
  }

  bool on_delivery_status(edge_slam_msgs::GetDeliveryStatus::Request&, edge_slam_msgs::GetDeliveryStatus::Response& res) {
    const edge_slam::DeliveryCounters c = delivery_->counters();
    auto s = session();
    res.created = s ? s->keyframe_ids_created().size() : 0;
    res.sent = c.sent;
    res.resent = c.resent;
    res.acknowledged = c.acknowledged;
    res.durable = c.durable;
    res.dropped_by_bound = c.dropped_by_bound;
    res.dropped_by_outbox = s ? s->outbox().evictions() : 0;
    res.queued = c.queued;
    res.edge_restarts = c.edge_restarts;
    res.seconds_since_ack = delivery_->seconds_since_ack(edge_slam::wall_clock_seconds());
    if (s) res.created_ids = s->keyframe_ids_created();
    return true;
  }


  // Bytes first: a corrupt array length must not reach roscpp's own (unchecked) deserializer.
  void on_map_update_bytes(const boost::shared_ptr<const edge_slam::RawMessage<edge_slam_msgs::MapUpdate>>& raw) {
    auto s = session();
    if (!s) return;
    auto msg = boost::make_shared<edge_slam_msgs::MapUpdate>();
    const edge_slam::DecodeStatus status = edge_slam::deserialize_checked(raw->bytes.data(), raw->bytes.size(), *msg);
    if (!status.ok) return reject_update(*s, status.error);
    on_map_update(s, *msg);
  }

  // Counted (rejected_invalid) and logged once per kind of problem, then throttled.
  void reject_update(MobileSession& s, const std::string& why) {
    s.count_invalid_update();
    const uint64_t same_kind = malformed_updates_.add(why);
    if (same_kind == 1) NODELET_ERROR("rejecting a malformed map update (first of its kind): %s", why.c_str());
    else
      NODELET_ERROR_THROTTLE(5.0, "rejecting malformed map updates (%lu so far): %s",
                             static_cast<unsigned long>(malformed_updates_.total()), why.c_str());
  }

  void on_map_update(const std::shared_ptr<MobileSession>& s, const edge_slam_msgs::MapUpdate& msg) {
    const size_t bytes = wire_size(msg);
    edge_slam::MapUpdateRecord update;
    const edge_slam::DecodeStatus status = edge_slam::from_message(msg, update);
    if (!status.ok) return reject_update(*s, status.error);
    // Published (edge wall clock) -> received and deserialised here.
    const double latency_ms = (edge_slam::wall_clock_seconds() - update.publish_stamp) * 1e3;
    const edge_slam::UpdateOutcome out = s->apply_update(update, ros::Time::now().toSec());
    const bool accepted = out.decision == edge_slam::UpdateDecision::kAccept && out.error.empty();
    metrics_.on_update(bytes, latency_ms, accepted, out.rebuild_ms);
    const char* kind = update.kind == edge_slam::MapUpdateKind::kRelocalization ? "relocalization" : "periodic";
    log_event("update", ros::Time::now().toSec(), update.seq, bytes, latency_ms, accepted ? out.rebuild_ms : -1,
              s->local_map_keyframes(), std::string(kind) + " " + (out.error.empty() ? to_string(out.decision) : "error"));
    if (!out.error.empty())
      NODELET_ERROR_THROTTLE(5.0, "map update %lu could not be applied: %s", static_cast<unsigned long>(update.seq),
                             out.error.c_str());
    else if (accepted)
      NODELET_INFO("applied %s map update %lu: %zu KeyFrames, %zu points, staged in %.1f ms, swapped in %.2f ms "
                   "(tracking paused)", kind, static_cast<unsigned long>(update.seq), out.keyframes, out.map_points,
                   out.stage_ms, out.rebuild_ms);
    else
      NODELET_DEBUG("map update %lu rejected: %s", static_cast<unsigned long>(update.seq), to_string(out.decision));
  }

  // The final decision on an update deferred by eq. (1): one more "update" row (no transfer).
  void report_deferred_update(const edge_slam::MobileSession& s, uint64_t seq, const edge_slam::UpdateOutcome& out) {
    const bool accepted = out.decision == edge_slam::UpdateDecision::kAccept && out.error.empty();
    metrics_.on_deferred_update(accepted, out.rebuild_ms);
    log_event("update", ros::Time::now().toSec(), seq, 0, -1, accepted ? out.rebuild_ms : -1, s.local_map_keyframes(),
              std::string("periodic ") + (out.error.empty() ? to_string(out.decision) : "error") + " after_deferral");
    if (!out.error.empty())
      NODELET_ERROR_THROTTLE(5.0, "map update %lu could not be applied: %s", static_cast<unsigned long>(seq),
                             out.error.c_str());
    else if (accepted)
      NODELET_INFO("applied deferred map update %lu: %zu KeyFrames, %zu points, rebuilt in %.1f ms",
                   static_cast<unsigned long>(seq), out.keyframes, out.map_points, out.rebuild_ms);
  }

  bool on_set_map_updates(edge_slam_msgs::SetMapUpdates::Request& req, edge_slam_msgs::SetMapUpdates::Response& res) {
    auto s = session();
    if (!s) {
      res.success = false;
      res.message = "tracking has not started yet (waiting for the first frame)";
      return true;
    }
    s->set_updates_enabled(req.enable);
    res.success = true;
    res.enabled = s->updates_enabled();
    res.message = res.enabled ? "map updates enabled" : "map updates disabled";
    NODELET_INFO("map-update controller: %s", res.message.c_str());
    log_event("controller", ros::Time::now().toSec(), 0, 0, -1, -1, -1, res.message);
    return true;
  }

  bool on_status(edge_slam_msgs::GetMapUpdateStatus::Request&, edge_slam_msgs::GetMapUpdateStatus::Response& res) {
    auto s = session();
    if (!s) return false;  // the caller sees "service call failed": not ready
    const edge_slam::MapUpdateCounters c = s->update_counters();
    res.enabled = s->updates_enabled();
    res.received = c.received;
    res.accepted = c.accepted;
    res.rejected_controller = c.rejected_controller;
    res.rejected_initializing = c.rejected_initializing;
    res.rejected_redundant = c.rejected_redundant;
    res.rejected_keyframe_rate = c.rejected_keyframe_rate;
    res.rejected_not_lost = c.rejected_not_lost;
    res.rejected_invalid = c.rejected_invalid;
    res.relocalization_applied = c.relocalization_applied;
    res.local_map_keyframes = static_cast<uint32_t>(s->local_map_keyframes());
    res.local_map_peak = static_cast<uint32_t>(s->local_map_peak());
    res.local_map_cap = static_cast<uint32_t>(s->local_map_cap());
    res.local_map_points = static_cast<uint32_t>(s->local_map_points());
    for (const auto& kf : s->local_map()->keyframes()) res.local_map_ids.push_back(kf->id());
    res.images_rejected_stamp = static_cast<uint32_t>(metrics_.images_rejected(ImageProblem::kStamp));
    res.images_rejected_encoding = static_cast<uint32_t>(metrics_.images_rejected(ImageProblem::kEncoding));
    res.images_rejected_size = static_cast<uint32_t>(metrics_.images_rejected(ImageProblem::kSize));
    res.images_rejected_depth = static_cast<uint32_t>(metrics_.images_rejected(ImageProblem::kDepth));
    res.keyframes_created = static_cast<uint32_t>(s->keyframes_sent());
    res.time_constraint = s->time_constraint();
    return true;
  }

  bool on_reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    auto s = session();
    if (!s) {
      res.success = false;
      res.message = "tracking has not started yet: nothing to reset";
      return true;
    }
    const bool sent = s->reset();
    {
      std::lock_guard<std::mutex> lock(output_mutex_);
      path_.poses.clear();
    }
    res.success = true;
    res.message = sent ? "reset: newest KeyFrame re-sent with its reset flag; Local-Map cleared"
                       : "reset: no KeyFrame yet; Local-Map cleared";
    NODELET_WARN("%s", res.message.c_str());
    log_event("reset", ros::Time::now().toSec(), 0, 0, -1, -1, static_cast<long>(s->local_map_keyframes()), "");
    return true;
  }

  void log_event(const char* event, double data_time, uint64_t seq, size_t bytes, double latency_ms,
                 double duration_ms, long map_keyframes, const std::string& detail) {
    events_->add(event, data_time, seq, bytes, latency_ms, duration_ms, map_keyframes, detail);
  }

  // Frames relative to their reference KeyFrame and KeyFrames relative to their parent: with the
  // edge's final KeyFrame poses these give the final trajectory (scripts/split_trajectory.py).
  void write_anchors(const edge_slam::TrackingResult& r, double stamp) {  // image thread only
    if (!anchors_.is_open() || !r.pose_valid) return;
    if (r.keyframe_id != edge_slam::kNoId && r.keyframe_parent_id != edge_slam::kNoId) {
      anchors_ << "K " << r.keyframe_id << ' ' << r.keyframe_parent_id << ' ';
      edge_slam::write_pose_fields(anchors_, r.T_parent_kf);
    }
    if (r.reference_kf_id != edge_slam::kNoId) {
      anchors_ << "F " << std::fixed << std::setprecision(6) << stamp << ' ' << r.reference_kf_id << ' ';
      edge_slam::write_pose_fields(anchors_, r.T_ref_c);
    }
    if (++anchor_lines_ % 30 == 0) anchors_.flush();
  }

  void publish_state(const edge_slam::TrackingResult& r) {
    std_msgs::String s;
    s.data = edge_slam::to_string(r.state);
    state_pub_.publish(s);
  }

  void publish_pose(const Eigen::Isometry3d& T_wc, const ros::Time& stamp) {
    geometry_msgs::TransformStamped tf = edge_slam::transform_to_message(T_wc, stamp, map_frame_, camera_frame_);
    tf_broadcaster_.sendTransform(tf);
    nav_msgs::Odometry odom;
    odom.header = tf.header;
    odom.child_frame_id = camera_frame_;
    odom.pose.pose = edge_slam::pose_to_message(T_wc);
    odometry_pub_.publish(odom);
    if (trajectory_.is_open()) {  // image thread only
      edge_slam::write_tum_pose(trajectory_, stamp.toSec(), T_wc);
      if (++trajectory_lines_ % 30 == 0) trajectory_.flush();
    }
    geometry_msgs::PoseStamped p;
    p.header = tf.header;
    p.pose = odom.pose.pose;
    std::lock_guard<std::mutex> lock(output_mutex_);
    path_.header = tf.header;
    path_.poses.push_back(p);
    // Bounded: the mobile's memory must stay flat on long runs.
    if (static_cast<int>(path_.poses.size()) > path_max_poses_) path_.poses.erase(path_.poses.begin());
    if (++path_counter_ % 5 == 0) path_pub_.publish(path_);  // 6 Hz at 30 fps is plenty for rviz
  }

  void publish_map() {
    auto s = session();
    if (!s) return;
    ros::Time stamp;
    {
      std::lock_guard<std::mutex> lock(output_mutex_);
      stamp = last_stamp_;
    }
    const auto map = s->local_map();
    if (cloud_pub_.getNumSubscribers() > 0)
      cloud_pub_.publish(edge_slam::to_point_cloud(map->map_points(), map_frame_, stamp));
    if (marker_pub_.getNumSubscribers() > 0)
      marker_pub_.publish(edge_slam::keyframe_markers(map->keyframes(), map_frame_, stamp, "local_map", 0.2f, 0.5f, 1.0f));
  }

  void publish_stats() {
    auto s = session();
    if (!s) return;
    edge_slam_msgs::Stats m = metrics_.stats(*s);
    const edge_slam::DeliveryCounters d = delivery_->counters();
    auto add = [&m](const char* name, double v) {
      m.names.push_back(name);
      m.values.push_back(v);
    };
    add("delivery_created", static_cast<double>(s->keyframes_sent()));
    add("delivery_sent", static_cast<double>(d.sent));
    add("delivery_resent", static_cast<double>(d.resent));
    add("delivery_acknowledged", static_cast<double>(d.acknowledged));
    add("delivery_durable", static_cast<double>(d.durable));
    add("delivery_dropped_by_bound", static_cast<double>(d.dropped_by_bound));
    add("delivery_queued", static_cast<double>(d.queued));
    add("delivery_edge_restarts", static_cast<double>(d.edge_restarts));
    add("link_seconds_since_ack", delivery_->seconds_since_ack(edge_slam::wall_clock_seconds()));
    m.header.stamp = ros::Time::now();
    stats_pub_.publish(m);
    events_->flush();
    write_outputs();
  }

  // metrics.json: rewritten every second and at shutdown, so a killed run still leaves one.
  void write_outputs() {
    auto s = session();
    if (!s || metrics_file_.empty()) return;
    std::lock_guard<std::mutex> lock(write_mutex_);
    try {
      metrics_.json(*s, dataset_)
          .object("malformed_updates", by_kind(malformed_updates_))
          .object("camera_frames_dropped", by_kind(rejected_frames_))
          .write(metrics_file_);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(30.0, "%s", e.what());
    }
  }

  static edge_slam::MetricsJson by_kind(const edge_slam::RejectionCounter& c) {  // reason kind -> count
    edge_slam::MetricsJson j;
    for (const auto& [kind, n] : c.by_kind()) j.integer(kind, static_cast<long long>(n));
    return j;
  }

  // Configuration (read once in onInit).
  edge_slam::NodeConfig config_;
  edge_slam::TrackingParams tracking_;
  edge_slam::OrbParams orb_;
  edge_slam::MobileSessionParams session_params_;
  std::unique_ptr<edge_slam::KeyFrameDelivery> delivery_;  // sender thread + ack callback (thread-safe)
  std::string map_frame_, camera_frame_, metrics_file_, dataset_;
  bool use_camera_info_ = true;
  double camera_info_timeout_ = 2.0;
  int path_max_poses_ = 20000;
  int image_queue_size_ = 2;

  // Set once on the image thread, read everywhere through session().
  std::shared_ptr<MobileSession> session_;
  edge_slam::PinholeCamera camera_;  // image thread only
  ros::WallTime first_image_wall_;   // image thread only
  bool warned_info_change_ = false;  // image thread only

  MobileMetrics metrics_;
  std::unique_ptr<edge_slam::EventLog> events_;
  std::ofstream trajectory_;  // image thread only (flushed there every 30 poses)
  uint64_t trajectory_lines_ = 0;
  std::ofstream anchors_;     // image thread only
  uint64_t anchor_lines_ = 0;
  std::mutex write_mutex_;    // metrics.json writers (timer, destructor)
  std::mutex output_mutex_;   // last_stamp_ and path_: image callback vs services and timers
  ros::Time last_stamp_;
  nav_msgs::Path path_;
  uint64_t path_counter_ = 0;
  edge_slam::RejectionCounter rejected_frames_, malformed_updates_;
  std::atomic<bool> running_{false};
  std::thread sender_;

  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::SubscriberFilter rgb_sub_, depth_sub_;
  std::unique_ptr<message_filters::Synchronizer<SyncPolicy>> sync_;
  ros::Publisher keyframe_pub_, floor_pub_, frame_pub_, odometry_pub_, path_pub_, cloud_pub_, marker_pub_, state_pub_, stats_pub_;
  ros::Subscriber update_sub_, info_sub_, ack_sub_;
  ros::ServiceServer set_srv_, status_srv_, reset_srv_, delivery_srv_;
  ros::WallTimer display_timer_, stats_timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
};

}  // namespace edge_slam_mobile

PLUGINLIB_EXPORT_CLASS(edge_slam_mobile::MobileNodelet, nodelet::Nodelet)
