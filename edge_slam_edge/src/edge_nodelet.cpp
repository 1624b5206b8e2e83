// The Edge-SLAM edge nodelet: ROS wiring around edge_slam::EdgeSystem (split/edge_system.h: the
// Global-Map session with Local-Mapping and Loop-Closing, its durability, run files, figures).
//   in:  keyframes (always taken; conditions 1-2 decide insertion), frames (relocalization),
//        keyframe_floor (std_msgs/UInt64: seqs the mobile will never send again)
//   out: map_updates (Local-Map Update Module timer; relocalization answers), keyframe_acks
//        (5 Hz, and as soon as Local-Mapping finishes a KeyFrame: received / durable / mapped
//        seqs and the boot id), ~global_map (PointCloud2), ~keyframes (MarkerArray),
//        ~keyframe_path (nav_msgs/Path), ~loops (one line per loop closed), ~stats (1 Hz)
//   srv: ~status (edge_slam_msgs/GetEdgeStatus: counters and KeyFrame id accounting),
//        ~save_map, ~load_map (edge_slam_msgs/MapFile; an empty path means ~checkpoint_file)
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame,
// ~stats_csv, ~metrics_file, ~keyframes_file (the Global-Map's KeyFrame poses and culled
// KeyFrames; empty = not written), ~checkpoint_file (empty = no persistence), ~restore_on_start
// (true); the checkpoint period is delivery/checkpoint_period in the slam config.
// Malformed messages (bytes that do not decode, checked before anything is allocated, or fields
// that break the record rules) are rejected, counted per topic and reason (~status
// malformed_keyframes / malformed_frames, ~stats keyframes_malformed / frames_malformed, per
// kind in metrics.json) and logged once per kind of problem, then throttled; nothing crashes.
#include <edge_slam/split/edge_system.h>
#include <edge_slam_bridge/ack_conversion.h>
#include <edge_slam_bridge/checked_subscriber.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <edge_slam_bridge/rosconsole_log.h>
#include <edge_slam_bridge/stats_message.h>
#include <edge_slam_msgs/MapFile.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt64.h>

#include <memory>

#include "edge_status.h"

namespace edge_slam_edge {

using Topic = edge_slam::EdgeSystem::Topic;

class EdgeNodelet : public nodelet::Nodelet {
 public:
  ~EdgeNodelet() override { checkpoint_timer_.stop(); }  // the system checkpoints once more as it goes

 private:
  void onInit() override {
    edge_slam::route_core_log_to_rosconsole(getName());
    ros::NodeHandle& nh = getMTNodeHandle();
    ros::NodeHandle& pnh = getMTPrivateNodeHandle();
    pnh.param<std::string>("map_frame", map_frame_, "map");
    try {
      const edge_slam::NodeConfig cfg = edge_slam::load_node_config(pnh);
      edge_slam::EdgeSystemSettings settings = edge_slam::load_edge_system_settings(cfg.slam);
      settings.camera = cfg.camera;
      settings.vocabulary = cfg.vocabulary;
      pnh.param<std::string>("checkpoint_file", settings.durability.checkpoint_file, "");
      pnh.param("restore_on_start", settings.restore_on_start, true);
      pnh.param<std::string>("stats_csv", settings.files.events, "");
      pnh.param<std::string>("metrics_file", settings.files.metrics, "");
      pnh.param<std::string>("keyframes_file", settings.files.keyframes, "");
      system_ = std::make_unique<edge_slam::EdgeSystem>(settings);
    } catch (const std::exception& e) {
      NODELET_FATAL("cannot start the edge: %s", e.what());
      return;
    }
    const edge_slam::EdgeSystemSettings& settings = system_->settings();
    update_pub_ = nh.advertise<edge_slam_msgs::MapUpdate>("map_updates", 10);
    display_ = {pnh.advertise<sensor_msgs::PointCloud2>("global_map", 1, true),
                pnh.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true), map_frame_, "global_map", 1.0f,
                0.55f, 0.0f};
    path_pub_ = pnh.advertise<nav_msgs::Path>("keyframe_path", 1, true);
    loop_pub_ = pnh.advertise<std_msgs::String>("loops", 10, true);
    stats_pub_ = pnh.advertise<edge_slam_msgs::Stats>("stats", 10);
    ack_pub_ = nh.advertise<edge_slam_msgs::KeyFrameAck>("keyframe_acks", 10);
    status_srv_ = pnh.advertiseService("status", &EdgeNodelet::on_status, this);
    save_srv_ = pnh.advertiseService("save_map", &EdgeNodelet::on_save_map, this);
    load_srv_ = pnh.advertiseService("load_map", &EdgeNodelet::on_load_map, this);
    floor_sub_ = nh.subscribe("keyframe_floor", 10, &EdgeNodelet::on_floor, this);
    keyframe_sub_ = edge_slam::subscribe_checked<edge_slam_msgs::KeyFrame, edge_slam::KeyFrameRecord>(
        nh, "keyframes", 1000, [this](const edge_slam::KeyFrameRecord& r, size_t bytes) { system_->receive_keyframe(r, bytes); },
        [this](const std::string& why, size_t bytes) { system_->reject(Topic::kKeyFrames, why, bytes); });
    frame_sub_ = edge_slam::subscribe_checked<edge_slam_msgs::Frame, edge_slam::FrameRecord>(
        nh, "frames", 5, [this](const edge_slam::FrameRecord& f, size_t bytes) { on_frame(f, bytes); },
        [this](const std::string& why, size_t bytes) { system_->reject(Topic::kFrames, why, bytes); });
    const double update_period = settings.session.update_period;
    update_timer_ = nh.createTimer(ros::Duration(update_period), [this](const ros::TimerEvent&) { send_update(); });
    display_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_map(); });
    stats_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_stats(); });
    // Acknowledgements at a steady 5 Hz: cheap, and a mobile that reconnects learns the state at once.
    ack_timer_ = nh.createWallTimer(ros::WallDuration(0.2), [this](const ros::WallTimerEvent&) { publish_ack(); });
    // As soon as Local-Mapping is done with a KeyFrame the mobile hears of it: its condition 2
    // waits for that (edge_slam/mobile_keyframe_pacing), like ORB-SLAM2's tracker reading its mapper.
    progress_timer_ = nh.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) {
      if (system_->mapping_progressed()) publish_ack();
    });
    if (!settings.durability.checkpoint_file.empty())
      checkpoint_timer_ = nh.createWallTimer(ros::WallDuration(settings.durability.checkpoint_period),
                                             [this](const ros::WallTimerEvent&) { system_->checkpoint("periodic"); });
    NODELET_INFO("edge ready: Local-Mapping + Loop-Closing on the Global-Map, updates every %.1f s", update_period);
  }

  void on_floor(const std_msgs::UInt64::ConstPtr& msg) { system_->skip_keyframes_through(msg->data); }
  void publish_ack() { ack_pub_.publish(edge_slam::to_message(system_->ack())); }

  void on_frame(const edge_slam::FrameRecord& frame, size_t bytes) {
    if (auto update = system_->answer_frame(frame, bytes)) publish(*update);
  }

  void send_update() {
    if (auto update = system_->periodic_update()) publish(*update);
  }

  void publish(edge_slam::MapUpdateRecord& update) {
    system_->stamp_for_publishing(update);
    const edge_slam_msgs::MapUpdate msg = edge_slam::to_message(update);
    update_pub_.publish(msg);
    system_->published(update, edge_slam::wire_size(msg), ros::Time::now().toSec());
  }

  bool on_status(edge_slam_msgs::GetEdgeStatus::Request&, edge_slam_msgs::GetEdgeStatus::Response& res) {
    fill(res, *system_);
    return true;
  }

  bool on_save_map(edge_slam_msgs::MapFile::Request& req, edge_slam_msgs::MapFile::Response& res) {
    res.ok = system_->save_map(req.path, &res.message);
    return true;
  }

  // A loaded map is a new session for the mobile (new boot id): it resends all it holds beyond
  // what the map says was received (split/edge_durability.h).
  bool on_load_map(edge_slam_msgs::MapFile::Request& req, edge_slam_msgs::MapFile::Response& res) {
    res.ok = system_->load_map(req.path, &res.message);
    return true;
  }

  void publish_map() {
    const auto map = system_->session().global_map();
    const ros::Time stamp = ros::Time::now();
    display_.publish(*map, stamp);
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

  // Loops announced, ~stats, and the run files (CSV, metrics.json, KeyFrames), every second.
  void publish_stats() {
    for (const std::string& line : system_->new_loops(ros::Time::now().toSec())) {
      std_msgs::String s;
      s.data = line;
      loop_pub_.publish(s);
    }
    stats_pub_.publish(edge_slam::to_message(system_->stats(), "edge", ros::Time::now()));
    system_->write_outputs();
  }

  std::unique_ptr<edge_slam::EdgeSystem> system_;  // set in onInit, before any callback
  std::string map_frame_;
  edge_slam::MapDisplay display_;
  ros::Publisher ack_pub_, update_pub_, path_pub_, loop_pub_, stats_pub_;
  ros::Subscriber keyframe_sub_, frame_sub_, floor_sub_;
  ros::ServiceServer status_srv_, save_srv_, load_srv_;
  ros::Timer update_timer_;
  ros::WallTimer display_timer_, stats_timer_, ack_timer_, progress_timer_, checkpoint_timer_;
};

}  // namespace edge_slam_edge

PLUGINLIB_EXPORT_CLASS(edge_slam_edge::EdgeNodelet, nodelet::Nodelet)
