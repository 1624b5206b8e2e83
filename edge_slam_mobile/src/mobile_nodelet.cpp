// The Edge-SLAM mobile nodelet: ROS wiring around edge_slam::MobileSystem (split/mobile_system.h:
// the tracking session, the KeyFrame sender, the run files, the figures).
//   in:  rgb/image + depth/image (approximate-time synchronised), rgb/camera_info (intrinsics;
//        YAML when absent), map_updates, keyframe_acks
//   out: keyframes (sender thread), keyframe_floor (std_msgs/UInt64: seqs the edge will never
//        get), frames (while lost), TF map -> camera, ~odometry, ~path, ~local_map (PointCloud2),
//        ~keyframes (MarkerArray), ~state, ~stats (1 Hz)
//   srv: ~set_map_updates, ~map_update_status (the map-update controller), ~reset, ~delivery_status
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame,
// ~camera_frame, ~use_camera_info (true), ~camera_info_timeout (s), ~stats_csv, ~metrics_file,
// ~trajectory_file, ~anchors_file (empty = not written), ~path_max_poses (3000: the newest poses
// ~path holds; bridge/bounded_path.h says why so few), ~image_queue_size (2:
// a live camera drops frames when tracking falls behind; evaluation sets it deep). Bad input is
// counted, logged once per kind of problem, then throttled, and dropped (malformed map_updates:
// rejected_invalid; camera frames: images_rejected_*); out-of-range parameters refuse the start.
#include <edge_slam/split/mobile_system.h>
#include <edge_slam/util/robot_ids.h>
#include <edge_slam_bridge/ack_conversion.h>
#include <edge_slam_bridge/bounded_path.h>
#include <edge_slam_bridge/checked_subscriber.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <edge_slam_bridge/ros_param.h>
#include <edge_slam_bridge/rosconsole_log.h>
#include <edge_slam_bridge/stats_message.h>
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

#include <atomic>
#include <memory>
#include <thread>

#include "camera_info_input.h"
#include "image_input.h"
#include "mobile_status.h"

namespace edge_slam_mobile {

using SyncPolicy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

class MobileNodelet : public nodelet::Nodelet {
 public:
  ~MobileNodelet() override {
    for (ros::WallTimer* t : {&display_timer_, &stats_timer_}) t->stop();  // none fires into a half-destroyed nodelet
    running_ = false;
    if (system_)
      if (auto s = system_->session()) s->outbox().close();
    if (sender_.joinable()) sender_.join();
  }

 private:
  void onInit() override {
    edge_slam::route_core_log_to_rosconsole(getName());
    ros::NodeHandle& nh = getMTNodeHandle();
    ros::NodeHandle& pnh = getMTPrivateNodeHandle();
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("camera_frame", camera_frame_, "camera");
    pnh.param("use_camera_info", use_camera_info_, true);
    int image_queue_size = 2;
    try {
      camera_info_timeout_ = edge_slam::param_in_range(pnh, "camera_info_timeout", 2.0, 0.0, 600.0);
      path_.set_max_poses(edge_slam::param_in_range(pnh, "path_max_poses", static_cast<int>(edge_slam::BoundedPath::kDefaultMaxPoses), 1, 1000000));
      image_queue_size = edge_slam::param_in_range(pnh, "image_queue_size", 2, 1, 10000);
      const edge_slam::NodeConfig config = edge_slam::load_node_config(pnh);
      yaml_camera_ = config.camera;
      edge_slam::MobileSystemSettings settings = edge_slam::load_mobile_system_settings(config.slam);
      settings.vocabulary = config.vocabulary;
      settings.session.robot_index = edge_slam::param_in_range(pnh, "robot_index", 0, 0, edge_slam::kMaxRobots - 1);
      pnh.param<std::string>("stats_csv", settings.files.events, "");
      pnh.param<std::string>("metrics_file", settings.files.metrics, "");
      pnh.param<std::string>("trajectory_file", settings.files.trajectory, "");
      pnh.param<std::string>("anchors_file", settings.files.anchors, "");
      pnh.param<std::string>("dataset", settings.dataset, "");
      system_ = std::make_unique<edge_slam::MobileSystem>(settings);
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start the mobile: %s", e.what());
      return;
    }
    keyframe_pub_ = nh.advertise<edge_slam_msgs::KeyFrame>("keyframes", 200);
    floor_pub_ = nh.advertise<std_msgs::UInt64>("keyframe_floor", 10);
    frame_pub_ = nh.advertise<edge_slam_msgs::Frame>("frames", 10);
    odometry_pub_ = pnh.advertise<nav_msgs::Odometry>("odometry", 10);
    path_pub_ = pnh.advertise<nav_msgs::Path>("path", 1, true);
    display_ = {pnh.advertise<sensor_msgs::PointCloud2>("local_map", 1, true),
                pnh.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true), map_frame_, "local_map", 0.2f,
                0.5f, 1.0f};
    state_pub_ = pnh.advertise<std_msgs::String>("state", 10, true);
    stats_pub_ = pnh.advertise<edge_slam_msgs::Stats>("stats", 10);
    ack_sub_ = nh.subscribe("keyframe_acks", 20, &MobileNodelet::on_ack, this);
    update_sub_ = edge_slam::subscribe_checked<edge_slam_msgs::MapUpdate, edge_slam::MapUpdateRecord>(
        nh, "map_updates", 5, [this](const edge_slam::MapUpdateRecord& u, size_t bytes) { on_update(u, bytes); },
        [this](const std::string& why, size_t) {
          if (system_->session()) system_->reject_update(why);  // before tracking: nothing to update
        });
    delivery_srv_ = pnh.advertiseService("delivery_status", &MobileNodelet::on_delivery_status, this);
    set_srv_ = pnh.advertiseService("set_map_updates", &MobileNodelet::on_set_map_updates, this);
    status_srv_ = pnh.advertiseService("map_update_status", &MobileNodelet::on_status, this);
    reset_srv_ = pnh.advertiseService("reset", &MobileNodelet::on_reset, this);

    // Images and camera_info on the single-threaded handle: frames are tracked one at a time, in
    // order, and the session is created there. Small queues by default: when tracking falls
    // behind, it goes on with the newest frame.
    ros::NodeHandle& st = getNodeHandle();
    it_ = std::make_unique<image_transport::ImageTransport>(st);
    rgb_sub_.subscribe(*it_, "rgb/image", static_cast<uint32_t>(image_queue_size));
    depth_sub_.subscribe(*it_, "depth/image", static_cast<uint32_t>(image_queue_size));
    sync_ = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(
        SyncPolicy(static_cast<uint32_t>(std::max(5, image_queue_size + 3))), rgb_sub_, depth_sub_);
    sync_->registerCallback(&MobileNodelet::on_rgbd, this);
    if (use_camera_info_) info_sub_ = st.subscribe("rgb/camera_info", 1, &MobileNodelet::on_camera_info, this);
    else start(yaml_camera_, "YAML (use_camera_info is false)");

    display_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_map(); });
    stats_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_stats(); });
    running_ = true;
    sender_ = std::thread([this] { send_keyframes(); });
    NODELET_INFO("mobile ready: Local-Map tracking, KeyFrame conditions 3-5, intrinsics from %s",
                 use_camera_info_ ? "camera_info (YAML if none arrives)" : "YAML");
  }

  // Image thread only (or onInit before any callback).
  void start(const edge_slam::PinholeCamera& c, const std::string& source) {
    try {
      system_->start(c);
      NODELET_INFO("tracking with camera '%s' %dx%d fx %.2f fy %.2f cx %.2f cy %.2f from %s", c.name.c_str(), c.width,
                   c.height, c.fx, c.fy, c.cx, c.cy, source.c_str());
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start tracking: %s", e.what());
    }
  }

  void on_camera_info(const sensor_msgs::CameraInfo::ConstPtr& info) {
    edge_slam::PinholeCamera cam;
    std::string error;
    const bool ok = camera_from_info(*info, yaml_camera_, cam, error);
    if (system_->session()) {
      if (ok && !same_intrinsics(cam, system_->camera()) && !warned_info_change_) {
        warned_info_change_ = true;
        NODELET_WARN("camera_info changed after tracking started (fx %.2f vs %.2f); keeping the first calibration",
                     cam.fx, system_->camera().fx);
      }
      return;
    }
    if (!ok) NODELET_ERROR("unusable camera_info (%s): using the YAML calibration", error.c_str());
    start(ok ? cam : yaml_camera_, ok ? "camera_info" : "YAML (camera_info refused)");
  }

  void on_rgbd(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth) {
    if (!system_->session()) {
      const ros::WallTime now = ros::WallTime::now();
      if (first_image_wall_.isZero()) first_image_wall_ = now;
      if ((now - first_image_wall_).toSec() < camera_info_timeout_) {
        NODELET_INFO_THROTTLE(5.0, "waiting for rgb/camera_info before tracking (at most %.1f s)", camera_info_timeout_);
        return;
      }
      NODELET_WARN("no camera_info within %.1f s: using the YAML calibration", camera_info_timeout_);
      start(yaml_camera_, "YAML (no camera_info)");
      if (!system_->session()) return;
    }
    ImageCheck check = convert_rgbd(rgb, depth, system_->camera(), last_stamp_.load());
    if (!check.ok) return system_->reject_image(check.problem, check.error);
    last_stamp_ = rgb->header.stamp;
    const double stamp = rgb->header.stamp.toSec();
    const edge_slam::TrackingResult r = system_->track(check.rgb, check.depth, stamp);
    std_msgs::String state;
    state.data = edge_slam::to_string(r.state);
    state_pub_.publish(state);
    if (r.pose_valid) publish_pose(r.T_cw.inverse(), rgb->header.stamp);
    if (auto frame = system_->relocalization_frame(stamp)) {
      const edge_slam_msgs::Frame msg = edge_slam::to_message(*frame);
      frame_pub_.publish(msg);
      system_->frame_sent(*frame, edge_slam::wire_size(msg), stamp);
    }
  }

  // The sender thread: outbox -> resend queue -> what is due now (split/keyframe_sender.h).
  void send_keyframes() {
    while (running_) {
      auto s = system_->session();
      if (!s) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      edge_slam::KeyFrameSender& sender = system_->sender();
      sender.take_from(s->outbox(), std::chrono::milliseconds(100), system_->now());
      const auto due = sender.due(system_->now(), keyframe_pub_.getNumSubscribers() > 0);
      for (const auto& record : due.records) {
        const edge_slam_msgs::KeyFrame msg = edge_slam::to_message(*record);
        keyframe_pub_.publish(msg);
        system_->keyframe_sent(*record, edge_slam::wire_size(msg));
      }
      if (due.floor) {
        std_msgs::UInt64 floor;
        floor.data = *due.floor;
        floor_pub_.publish(floor);
      }
    }
  }

  void on_ack(const edge_slam_msgs::KeyFrameAck::ConstPtr& msg) { system_->on_ack(edge_slam::from_message(*msg)); }

  void on_update(const edge_slam::MapUpdateRecord& update, size_t bytes) {
    if (system_->session()) system_->apply_update(update, bytes, ros::Time::now().toSec());
  }

  bool on_delivery_status(edge_slam_msgs::GetDeliveryStatus::Request&, edge_slam_msgs::GetDeliveryStatus::Response& res) {
    fill(res, *system_, system_->session().get());
    return true;
  }

  bool on_set_map_updates(edge_slam_msgs::SetMapUpdates::Request& req, edge_slam_msgs::SetMapUpdates::Response& res) {
    const auto s = system_->session();
    res.success = s != nullptr;
    res.message = s ? system_->set_updates_enabled(req.enable, ros::Time::now().toSec())
                    : "tracking has not started yet (waiting for the first frame)";
    res.enabled = s && s->updates_enabled();
    return true;
  }

  bool on_status(edge_slam_msgs::GetMapUpdateStatus::Request&, edge_slam_msgs::GetMapUpdateStatus::Response& res) {
    const auto s = system_->session();
    if (!s) return false;  // the caller sees "service call failed": not ready
    fill(res, *system_, *s);
    return true;
  }

  bool on_reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    res.success = system_->session() != nullptr;
    if (!res.success) {
      res.message = "tracking has not started yet: nothing to reset";
      return true;
    }
    res.message = system_->reset(ros::Time::now().toSec());
    path_.clear();
    return true;
  }

  void publish_pose(const Eigen::Isometry3d& T_wc, const ros::Time& stamp) {
    geometry_msgs::TransformStamped tf = edge_slam::transform_to_message(T_wc, stamp, map_frame_, camera_frame_);
    tf_broadcaster_.sendTransform(tf);
    nav_msgs::Odometry odom;
    odom.header = tf.header;
    odom.child_frame_id = camera_frame_;
    odom.pose.pose = edge_slam::pose_to_message(T_wc);
    odometry_pub_.publish(odom);
    geometry_msgs::PoseStamped p;
    p.header = tf.header;
    p.pose = odom.pose.pose;
    // Latched: roscpp would serialise the whole path at each publish even with nobody listening.
    // The poses are kept either way, so a subscriber that comes later gets them at the next one.
    path_.add(p, [this](const nav_msgs::Path& path) {
      if (path_pub_.getNumSubscribers() > 0) path_pub_.publish(path);
    });
  }

  void publish_map() {
    if (const auto s = system_->session()) display_.publish(*s->local_map(), last_stamp_.load());
  }

  // ~stats and the run files (CSV, trajectory, anchors, metrics.json), every second.
  void publish_stats() {
    if (!system_->session()) return;
    stats_pub_.publish(edge_slam::to_message(system_->stats(), "mobile", ros::Time::now()));
    system_->write_outputs();
  }

  std::unique_ptr<edge_slam::MobileSystem> system_;  // set in onInit, before any callback
  edge_slam::PinholeCamera yaml_camera_;
  std::string map_frame_, camera_frame_;
  bool use_camera_info_ = true;
  double camera_info_timeout_ = 2.0;
  ros::WallTime first_image_wall_;   // image thread only
  bool warned_info_change_ = false;  // image thread only
  std::atomic<ros::Time> last_stamp_;  // the image callback writes, the display timer reads
  edge_slam::BoundedPath path_;
  std::atomic<bool> running_{false};
  std::thread sender_;

  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::SubscriberFilter rgb_sub_, depth_sub_;
  std::unique_ptr<message_filters::Synchronizer<SyncPolicy>> sync_;
  ros::Publisher keyframe_pub_, floor_pub_, frame_pub_, odometry_pub_, path_pub_, state_pub_, stats_pub_;
  edge_slam::MapDisplay display_;
  ros::Subscriber update_sub_, info_sub_, ack_sub_;
  ros::ServiceServer set_srv_, status_srv_, reset_srv_, delivery_srv_;
  ros::WallTimer display_timer_, stats_timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
};

}  // namespace edge_slam_mobile

PLUGINLIB_EXPORT_CLASS(edge_slam_mobile::MobileNodelet, nodelet::Nodelet)
