// The Edge-SLAM mobile nodelet: ROS plumbing around edge_slam::MobileSession.
//   in:  rgb/image + depth/image (image_transport, approximate-time synchronised), map_updates
//   out: keyframes (sender thread), frames (while lost), TF map -> camera, ~odometry, ~path,
//        ~local_map (PointCloud2), ~state
//   srv: ~set_map_updates, ~map_update_status (the map-update controller), ~reset
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame,
// ~camera_frame. Bad input is logged once (throttled) with what was expected, counted, and
// dropped; the nodelet keeps running.
#include <cv_bridge/cv_bridge.h>
#include <edge_slam/module/mobile_session.h>
#include <edge_slam/module/tracking_params.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/message_conversion.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_msgs/GetMapUpdateStatus.h>
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
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <mutex>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "image_input.h"
#include <edge_slam_bridge/pose_conversion.h>

namespace edge_slam_mobile {

using edge_slam::MobileSession;
using SyncPolicy = message_filters::sync_policies::ApproximateTime<sensor_msgs::Image, sensor_msgs::Image>;

class MobileNodelet : public nodelet::Nodelet {
 public:
  ~MobileNodelet() override {
    running_ = false;
    if (session_) session_->outbox().close();
    if (sender_.joinable()) sender_.join();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getMTNodeHandle();
    ros::NodeHandle& pnh = getMTPrivateNodeHandle();
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("camera_frame", camera_frame_, "camera");
    try {
      const edge_slam::NodeConfig cfg = edge_slam::load_node_config(pnh);
      camera_ = cfg.camera;
      edge_slam::TrackingParams tracking = edge_slam::load_tracking_params(cfg.slam);
      tracking.conditions = edge_slam::KeyFrameConditionSet::kMobile;  // 1-2 run on the edge (paper 4.4)
      session_ = std::make_unique<MobileSession>(camera_, edge_slam::load_orb_params(cfg.slam), tracking,
                                                 cfg.vocabulary, edge_slam::load_mobile_session_params(cfg.slam),
                                                 edge_slam::RgbEncoding::kRgb);
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start the mobile: %s", e.what());
      return;
    }

    keyframe_pub_ = nh.advertise<edge_slam_msgs::KeyFrame>("keyframes", 200);
    frame_pub_ = nh.advertise<edge_slam_msgs::Frame>("frames", 10);
    odometry_pub_ = pnh.advertise<nav_msgs::Odometry>("odometry", 10);
    path_pub_ = pnh.advertise<nav_msgs::Path>("path", 1, true);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("local_map", 1, true);
    state_pub_ = pnh.advertise<std_msgs::String>("state", 10, true);
    update_sub_ = nh.subscribe("map_updates", 5, &MobileNodelet::on_map_update, this);
    set_srv_ = pnh.advertiseService("set_map_updates", &MobileNodelet::on_set_map_updates, this);
    status_srv_ = pnh.advertiseService("map_update_status", &MobileNodelet::on_status, this);
    reset_srv_ = pnh.advertiseService("reset", &MobileNodelet::on_reset, this);

    // Images on the single-threaded handle: frames are tracked one at a time, in order. Small
    // queues: after a pause (an update being applied) tracking resumes with the newest frame.
    it_ = std::make_unique<image_transport::ImageTransport>(getNodeHandle());
    rgb_sub_.subscribe(*it_, "rgb/image", 2);
    depth_sub_.subscribe(*it_, "depth/image", 2);
    sync_ = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(SyncPolicy(5), rgb_sub_, depth_sub_);
    sync_->registerCallback(&MobileNodelet::on_rgbd, this);
    cloud_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_local_map(); });

    running_ = true;
    sender_ = std::thread([this] { send_keyframes(); });
    NODELET_INFO("mobile ready: camera '%s' %dx%d, Local-Map tracking, KeyFrame conditions 3-5",
                 camera_.name.c_str(), camera_.width, camera_.height);
  }

  void on_rgbd(const sensor_msgs::ImageConstPtr& rgb, const sensor_msgs::ImageConstPtr& depth) {
    ImageCheck check = convert_rgbd(*rgb, *depth, camera_, last_stamp_);
    if (!check.ok) {
      const uint64_t dropped = ++rejected_frames_;
      NODELET_ERROR_THROTTLE(5.0, "dropping camera frame (%lu dropped so far): %s", static_cast<unsigned long>(dropped),
                             check.error.c_str());
      return;
    }
    {
      std::lock_guard<std::mutex> lock(output_mutex_);
      last_stamp_ = rgb->header.stamp;
    }
    const edge_slam::TrackingResult r = session_->track(check.rgb, check.depth, rgb->header.stamp.toSec());
    if (!r.message.empty() && r.state != edge_slam::TrackingState::kOk)
      NODELET_WARN_THROTTLE(5.0, "tracking: %s", r.message.c_str());
    publish_state(r);
    if (r.pose_valid) publish_pose(r.T_cw.inverse(), rgb->header.stamp);
    if (auto frame = session_->take_relocalization_frame(rgb->header.stamp.toSec()))
      frame_pub_.publish(edge_slam::to_message(*frame));
  }

  // Drains the outbox: tracking only ever pushes, so network trouble never stalls it.
  void send_keyframes() {
    while (running_) {
      std::optional<edge_slam::KeyFrameRecord> record = session_->outbox().pop_for(std::chrono::milliseconds(200));
      if (!record) continue;
      keyframe_pub_.publish(edge_slam::to_message(*record));
    }
  }

  void on_map_update(const edge_slam_msgs::MapUpdate::ConstPtr& msg) {
    edge_slam::MapUpdateRecord update;
    const edge_slam::DecodeStatus status = edge_slam::from_message(*msg, update);
    if (!status.ok) {
      session_->count_invalid_update();
      NODELET_ERROR_THROTTLE(5.0, "rejecting a malformed map update: %s", status.error.c_str());
      return;
    }
    const edge_slam::UpdateOutcome out = session_->apply_update(update, ros::Time::now().toSec());
    if (!out.error.empty())
      NODELET_ERROR_THROTTLE(5.0, "map update %lu could not be applied: %s", static_cast<unsigned long>(update.seq),
                             out.error.c_str());
    else if (out.decision == edge_slam::UpdateDecision::kAccept)
      NODELET_INFO("applied map update %lu: %zu KeyFrames, %zu points, rebuilt in %.1f ms",
                   static_cast<unsigned long>(update.seq), out.keyframes, out.map_points, out.rebuild_ms);
    else
      NODELET_DEBUG("map update %lu rejected: %s", static_cast<unsigned long>(update.seq), to_string(out.decision));
  }

  bool on_set_map_updates(edge_slam_msgs::SetMapUpdates::Request& req, edge_slam_msgs::SetMapUpdates::Response& res) {
    session_->set_updates_enabled(req.enable);
    res.success = true;
    res.enabled = session_->updates_enabled();
    res.message = res.enabled ? "map updates enabled" : "map updates disabled";
    NODELET_INFO("map-update controller: %s", res.message.c_str());
    return true;
  }

  bool on_status(edge_slam_msgs::GetMapUpdateStatus::Request&, edge_slam_msgs::GetMapUpdateStatus::Response& res) {
    const edge_slam::MapUpdateCounters c = session_->update_counters();
    res.enabled = session_->updates_enabled();
    res.received = c.received;
    res.accepted = c.accepted;
    res.rejected_controller = c.rejected_controller;
    res.rejected_initializing = c.rejected_initializing;
    res.rejected_redundant = c.rejected_redundant;
    res.rejected_keyframe_rate = c.rejected_keyframe_rate;
    res.rejected_not_lost = c.rejected_not_lost;
    res.rejected_invalid = c.rejected_invalid;
    res.relocalization_applied = c.relocalization_applied;
    res.local_map_keyframes = static_cast<uint32_t>(session_->local_map_keyframes());
    res.time_constraint = session_->time_constraint();
    return true;
  }

  bool on_reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    const bool sent = session_->reset();
    {
      std::lock_guard<std::mutex> lock(output_mutex_);
      path_.poses.clear();
    }
    res.success = true;
    res.message = sent ? "reset: newest KeyFrame re-sent with its reset flag; Local-Map cleared"
                       : "reset: no KeyFrame yet; Local-Map cleared";
    NODELET_WARN("%s", res.message.c_str());
    return true;
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
    geometry_msgs::PoseStamped p;
    p.header = tf.header;
    p.pose = odom.pose.pose;
    std::lock_guard<std::mutex> lock(output_mutex_);
    path_.header = tf.header;
    path_.poses.push_back(p);
    path_pub_.publish(path_);
  }

  void publish_local_map() {
    if (!session_ || cloud_pub_.getNumSubscribers() == 0) return;
    ros::Time stamp;
    {
      std::lock_guard<std::mutex> lock(output_mutex_);
      stamp = last_stamp_;
    }
    cloud_pub_.publish(edge_slam::to_point_cloud(session_->local_map()->map_points(), map_frame_, stamp));
  }

  edge_slam::PinholeCamera camera_;
  std::unique_ptr<MobileSession> session_;
  std::string map_frame_, camera_frame_;
  std::mutex output_mutex_;  // last_stamp_ and path_: image callback vs services and timers
  ros::Time last_stamp_;
  std::atomic<uint64_t> rejected_frames_{0};
  std::atomic<bool> running_{false};
  std::thread sender_;
  nav_msgs::Path path_;

  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::SubscriberFilter rgb_sub_, depth_sub_;
  std::unique_ptr<message_filters::Synchronizer<SyncPolicy>> sync_;
  ros::Publisher keyframe_pub_, frame_pub_, odometry_pub_, path_pub_, cloud_pub_, state_pub_;
  ros::Subscriber update_sub_;
  ros::ServiceServer set_srv_, status_srv_, reset_srv_;
  ros::WallTimer cloud_timer_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
};

}  // namespace edge_slam_mobile

PLUGINLIB_EXPORT_CLASS(edge_slam_mobile::MobileNodelet, nodelet::Nodelet)
