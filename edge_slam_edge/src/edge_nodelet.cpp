// The Edge-SLAM edge nodelet: ROS plumbing around edge_slam::EdgeSession.
//   in:  keyframes (always taken; conditions 1-2 decide insertion), frames (relocalization)
//   out: map_updates (Local-Map Update Module timer; relocalization answers), ~global_map
//        (PointCloud2), ~keyframe_path (KeyFrame poses as nav_msgs/Path)
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame.
// Malformed messages are rejected with one throttled error and counted; nothing crashes.
#include <edge_slam/module/edge_session.h>
#include <edge_slam/module/tracking_params.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/message_conversion.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <atomic>
#include <memory>

namespace edge_slam_edge {

class EdgeNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getMTNodeHandle();
    ros::NodeHandle& pnh = getMTPrivateNodeHandle();
    pnh.param<std::string>("map_frame", map_frame_, "map");
    double update_period = 5.0;
    try {
      const edge_slam::NodeConfig cfg = edge_slam::load_node_config(pnh);
      const edge_slam::OrbParams orb = edge_slam::load_orb_params(cfg.slam);
      update_period = cfg.slam.get_double_or("edge_slam/update_period", 5.0, 0.05, 3600.0);
      session_ = std::make_unique<edge_slam::EdgeSession>(cfg.camera, orb.num_levels, orb.scale_factor,
                                                          cfg.vocabulary, edge_slam::load_edge_session_params(cfg.slam));
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start the edge: %s", e.what());
      return;
    }
    update_pub_ = nh.advertise<edge_slam_msgs::MapUpdate>("map_updates", 10);
    cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("global_map", 1, true);
    path_pub_ = pnh.advertise<nav_msgs::Path>("keyframe_path", 1, true);
    keyframe_sub_ = nh.subscribe("keyframes", 1000, &EdgeNodelet::on_keyframe, this);
    frame_sub_ = nh.subscribe("frames", 5, &EdgeNodelet::on_frame, this);
    update_timer_ = nh.createTimer(ros::Duration(update_period), [this](const ros::TimerEvent&) { send_update(); });
    display_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_map(); });
    NODELET_INFO("edge ready: Local-Mapping + Loop-Closing on the Global-Map, updates every %.1f s", update_period);
  }

  void on_keyframe(const edge_slam_msgs::KeyFrame::ConstPtr& msg) {
    edge_slam::KeyFrameRecord record;
    const edge_slam::DecodeStatus status = edge_slam::from_message(*msg, record);
    if (!status.ok) {
      const uint64_t rejected = ++invalid_;
      NODELET_ERROR_THROTTLE(5.0, "rejecting a malformed KeyFrame (%lu malformed messages so far): %s",
                             static_cast<unsigned long>(rejected), status.error.c_str());
      return;
    }
    std::string error;
    const edge_slam::KeyFrameVerdict v = session_->receive_keyframe(record, &error);
    if (v == edge_slam::KeyFrameVerdict::kInvalid)
      NODELET_ERROR_THROTTLE(5.0, "KeyFrame %u refused: %s", record.id, error.c_str());
    else if (v == edge_slam::KeyFrameVerdict::kReset)
      NODELET_WARN("reset requested by the mobile (KeyFrame %u): Global-Map cleared", record.id);
    else
      NODELET_DEBUG("KeyFrame %u: %s", record.id, edge_slam::to_string(v));
  }

  void on_frame(const edge_slam_msgs::Frame::ConstPtr& msg) {
    edge_slam::FrameRecord record;
    const edge_slam::DecodeStatus status = edge_slam::from_message(*msg, record);
    if (!status.ok) {
      const uint64_t rejected = ++invalid_;
      NODELET_ERROR_THROTTLE(5.0, "rejecting a malformed Frame (%lu malformed messages so far): %s",
                             static_cast<unsigned long>(rejected), status.error.c_str());
      return;
    }
    std::string error;
    auto update = session_->build_relocalization_update(record, ros::Time::now().toSec(), &error);
    if (!error.empty()) NODELET_ERROR_THROTTLE(5.0, "Frame %u refused: %s", record.id, error.c_str());
    if (update) publish(*update);
  }

  void send_update() {
    if (auto update = session_->build_local_map_update(ros::Time::now().toSec())) publish(*update);
  }

  void publish(edge_slam::MapUpdateRecord& update) {
    update.publish_stamp = ros::Time::now().toSec();
    update_pub_.publish(edge_slam::to_message(update));
  }

  void publish_map() {
    if (!session_) return;
    const auto map = session_->global_map();
    const ros::Time stamp = ros::Time::now();
    if (cloud_pub_.getNumSubscribers() > 0) {
      cloud_pub_.publish(edge_slam::to_point_cloud(map->map_points(), map_frame_, stamp));
    }
    nav_msgs::Path path;
    path.header.frame_id = map_frame_;
    path.header.stamp = stamp;
    for (const auto& kf : map->keyframes()) {
      geometry_msgs::PoseStamped p;
      p.header.frame_id = map_frame_;
      p.header.stamp = ros::Time(kf->stamp());
      p.pose = edge_slam::pose_to_message(kf->T_wc());
      path.poses.push_back(p);
    }
    path_pub_.publish(path);
  }

  std::unique_ptr<edge_slam::EdgeSession> session_;
  std::string map_frame_;
  std::atomic<uint64_t> invalid_{0};
  ros::Publisher update_pub_, cloud_pub_, path_pub_;
  ros::Subscriber keyframe_sub_, frame_sub_;
  ros::Timer update_timer_;
  ros::WallTimer display_timer_;
};

}  // namespace edge_slam_edge

PLUGINLIB_EXPORT_CLASS(edge_slam_edge::EdgeNodelet, nodelet::Nodelet)
