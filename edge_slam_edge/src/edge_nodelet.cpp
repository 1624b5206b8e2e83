// The Edge-SLAM edge nodelet: ROS wiring around edge_slam::EdgeSystem (split/edge_system.h: the
// Global-Map session with Local-Mapping and Loop-Closing, its durability, run files, figures).
//   in:  keyframes (always taken; conditions 1-2 decide insertion), frames (relocalization),
//        keyframe_floor (std_msgs/UInt64: seqs the mobile will never send again)
//   out: map_updates (Local-Map Update Module timer; relocalization answers), keyframe_acks
//        (5 Hz, and as soon as Local-Mapping finishes a KeyFrame: received / durable / mapped
//        seqs and the boot id), ~global_map (PointCloud2), ~keyframes (MarkerArray),
//        ~keyframe_path (nav_msgs/Path), ~loops (one line per loop closed), ~stats (1 Hz)
//   srv: ~status (edge_slam_msgs/GetEdgeStatus: counters and KeyFrame id accounting; with
//        several mobiles robot 0's, and each robot's at /<robot>/edge_slam/edge_status),
//        ~save_map, ~load_map (edge_slam_msgs/MapFile; an empty path means ~checkpoint_file)
// Several mobiles (~mobiles: [robot1, robot2], robot i sending with ~robot_index i): each
// robot's topics above live under /<robot>/edge_slam/, the maps of robots that see the same
// place are merged (~merges: edge_slam_msgs/MapMerge) and TF world -> <robot>/map is published
// (static) once a robot's map joins robot 0's; ~global_map and ~keyframes are in `world`.
// Parameters: ~camera_config, ~slam_config, ~vocabulary (files; see config/), ~map_frame,
// ~stats_csv, ~metrics_file, ~keyframes_file (the Global-Map's KeyFrame poses and culled
// KeyFrames; empty = not written), ~checkpoint_file (empty = no persistence), ~restore_on_start
// (true); the checkpoint period is delivery/checkpoint_period in the slam config.
// Malformed messages (bytes that do not decode, checked before anything is allocated, or fields
// that break the record rules) are rejected, counted per topic and reason (~status
// malformed_keyframes / malformed_frames, ~stats keyframes_malformed / frames_malformed, per
// kind in metrics.json) and logged once per kind of problem, then throttled; nothing crashes.
#include <edge_slam/module/update_trigger.h>
#include <edge_slam/split/edge_system.h>
#include <edge_slam/util/robot_ids.h>
#include <edge_slam_bridge/ack_conversion.h>
#include <edge_slam_bridge/checked_subscriber.h>
#include <edge_slam_bridge/map_display.h>
#include <edge_slam_bridge/node_config.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <edge_slam_bridge/rosconsole_log.h>
#include <edge_slam_bridge/stats_message.h>
#include <edge_slam_msgs/MapFile.h>
#include <edge_slam_msgs/MapMerge.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt64.h>

#include <algorithm>
#include <memory>
#include <vector>

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
    pnh.param("mobiles", mobiles_, std::vector<std::string>{});
    for (size_t i = 0; i < mobiles_.size(); ++i) {
      std::string why;
      if (!ros::names::validate(mobiles_[i], why) || mobiles_[i].empty() || mobiles_[i].front() == '/')
        why = "'" + mobiles_[i] + "' is not a relative ROS name" + (why.empty() ? "" : ": " + why);
      else if (std::find(mobiles_.begin(), mobiles_.begin() + i, mobiles_[i]) != mobiles_.begin() + i)
        why = "'" + mobiles_[i] + "' is listed twice";
      if (!why.empty()) {
        NODELET_FATAL("cannot start the edge: ~mobiles entry %zu: %s (expected e.g. [robot1, robot2])", i, why.c_str());
        return;
      }
    }
    if (!mobiles_.empty()) map_frame_ = "world";  // the merged Global-Map
    try {
      const edge_slam::NodeConfig cfg = edge_slam::load_node_config(pnh);
      edge_slam::EdgeSystemSettings settings = edge_slam::load_edge_system_settings(cfg.slam);
      settings.camera = cfg.camera;
      settings.vocabulary = cfg.vocabulary;
      settings.session.robots = mobiles_.empty() ? 1 : static_cast<int>(mobiles_.size());
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
    display_ = {pnh.advertise<sensor_msgs::PointCloud2>("global_map", 1, true),
                pnh.advertise<visualization_msgs::MarkerArray>("keyframes", 1, true), map_frame_, "global_map", 1.0f,
                0.55f, 0.0f};
    path_pub_ = pnh.advertise<nav_msgs::Path>("keyframe_path", 1, true);
    loop_pub_ = pnh.advertise<std_msgs::String>("loops", 10, true);
    merge_pub_ = pnh.advertise<edge_slam_msgs::MapMerge>("merges", 10, true);
    stats_pub_ = pnh.advertise<edge_slam_msgs::Stats>("stats", 10);
    status_srv_ = pnh.advertiseService("status", &EdgeNodelet::on_status, this);
    save_srv_ = pnh.advertiseService("save_map", &EdgeNodelet::on_save_map, this);
    load_srv_ = pnh.advertiseService("load_map", &EdgeNodelet::on_load_map, this);
    for (int r = 0; r < system_->robots(); ++r) {
      if (mobiles_.empty()) {
        wire_robot(r, nh);
        continue;
      }
      ros::NodeHandle rnh("/" + mobiles_[r] + "/edge_slam");
      rnh.setCallbackQueue(nh.getCallbackQueue());  // the nodelet's threads, as for one mobile
      wire_robot(r, rnh);
      robots_[r].status_srv = rnh.advertiseService<edge_slam_msgs::GetEdgeStatus::Request, edge_slam_msgs::GetEdgeStatus::Response>(
          "edge_status", [this, r](auto&, auto& res) { return fill(res, *system_, r), true; });
    }
    const double update_period = settings.session.update_period;
    // The period runs on the data clock (the bag's /clock when replaying), polled at 20 Hz from a
    // wall timer: a ros::Timer on sim time makes roscpp's timer thread wake every millisecond,
    // which took cores from the mobile's tracking when both run on one PC (module/update_trigger.h).
    update_schedule_ = std::make_unique<edge_slam::PeriodicSchedule>(update_period);
    update_timer_ = nh.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) {
      const ros::Time now = ros::Time::now();  // zero until the first /clock of a replay
      if (now.isZero() || !update_schedule_->due(now.toSec())) return;
      for (int r = 0; r < system_->robots(); ++r) send_update(r);
    });
    display_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_map(); });
    stats_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { publish_stats(); });
    // Acknowledgements at a steady 5 Hz: cheap, and a mobile that reconnects learns the state at once.
    ack_timer_ = nh.createWallTimer(ros::WallDuration(0.2), [this](const ros::WallTimerEvent&) {
      for (int r = 0; r < system_->robots(); ++r) publish_ack(r);
    });
    // As soon as Local-Mapping is done with a KeyFrame the mobile hears of it: its condition 2
    // waits for that (edge_slam/mobile_keyframe_pacing), like ORB-SLAM2's tracker reading its mapper.
    progress_timer_ = nh.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) {
      for (int r = 0; r < system_->robots(); ++r)
        if (system_->mapping_progressed(r)) {
          publish_ack(r);
          // The paper's "difference deemed large": an update before the timer (module/update_trigger.h).
          if (auto update = system_->divergence_update(r)) publish(*update, r);
        }
    });
    if (!settings.durability.checkpoint_file.empty())
      checkpoint_timer_ = nh.createWallTimer(ros::WallDuration(settings.durability.checkpoint_period),
                                             [this](const ros::WallTimerEvent&) { system_->checkpoint("periodic"); });
    publish_world_frames();
    NODELET_INFO("edge ready: Local-Mapping + Loop-Closing on the Global-Map for %d mobile(s), updates every %.1f s",
                 system_->robots(), update_period);
  }

  // One mobile's topics: KeyFrames, Frames and the floor in; updates and acknowledgements out.
  void wire_robot(int r, ros::NodeHandle rnh) {
    Robot& robot = robots_.emplace_back();
    robot.update_pub = rnh.advertise<edge_slam_msgs::MapUpdate>("map_updates", 10);
    robot.ack_pub = rnh.advertise<edge_slam_msgs::KeyFrameAck>("keyframe_acks", 10);
    robot.floor_sub = rnh.subscribe<std_msgs::UInt64>(
        "keyframe_floor", 10, [this, r](const std_msgs::UInt64::ConstPtr& m) { system_->skip_keyframes_through(m->data, r); });
    robot.keyframe_sub = edge_slam::subscribe_checked<edge_slam_msgs::KeyFrame, edge_slam::KeyFrameRecord>(
        rnh, "keyframes", 1000, [this, r](const edge_slam::KeyFrameRecord& k, size_t bytes) { system_->receive_keyframe(k, bytes, r); },
        [this](const std::string& why, size_t bytes) { system_->reject(Topic::kKeyFrames, why, bytes); });
    robot.frame_sub = edge_slam::subscribe_checked<edge_slam_msgs::Frame, edge_slam::FrameRecord>(
        rnh, "frames", 5, [this, r](const edge_slam::FrameRecord& f, size_t bytes) {
          if (auto update = system_->answer_frame(f, bytes, r)) publish(*update, r);
        },
        [this](const std::string& why, size_t bytes) { system_->reject(Topic::kFrames, why, bytes); });
  }

  void publish_ack(int r) { robots_[r].ack_pub.publish(edge_slam::to_message(system_->ack(r))); }

  void send_update(int r) {
    if (auto update = system_->periodic_update(r)) publish(*update, r);
  }

  void publish(edge_slam::MapUpdateRecord& update, int r) {
    system_->stamp_for_publishing(update);
    const edge_slam_msgs::MapUpdate msg = edge_slam::to_message(update);
    robots_[r].update_pub.publish(msg);
    system_->published(update, edge_slam::wire_size(msg), ros::Time::now().toSec(), r);
  }

  // Several mobiles: TF world -> <robot>/map for every robot whose map is in the world (static:
  // a placement changes only at a merge or a robot's reset; re-sent then).
  void publish_world_frames() {
    if (mobiles_.empty()) return;
    // Sent again when a robot is placed or a placement moved (robot frames follow their
    // anchors after each loop correction: RobotFrames::follow_anchors).
    std::vector<geometry_msgs::TransformStamped> placed;
    std::vector<std::optional<Eigen::Isometry3d>> now(system_->robots());
    bool moved = world_frames_sent_.size() != now.size();
    for (int r = 0; r < system_->robots(); ++r) {
      now[r] = system_->T_world_robot(r);
      if (!now[r]) continue;
      placed.push_back(edge_slam::transform_to_message(*now[r], ros::Time::now(), "world", mobiles_[r] + "/map"));
      moved = moved || !world_frames_sent_[r] || !world_frames_sent_[r]->isApprox(*now[r], 1e-4);
    }
    if (moved && !placed.empty()) tf_static_.sendTransform(placed);
    world_frames_sent_ = std::move(now);
  }

  void publish_merges() {
    for (const edge_slam::MergeEvent& e : system_->new_merges(ros::Time::now().toSec())) {
      edge_slam_msgs::MapMerge m;
      m.header.stamp = ros::Time::now();
      m.header.frame_id = "world";
      const auto name = [this](uint32_t kf) {
        const int r = edge_slam::robot_of_keyframe(kf);
        return r >= 0 && r < static_cast<int>(mobiles_.size()) ? mobiles_[r] : std::to_string(r);
      };
      m.robot = name(e.current_kf_id);
      m.into_robot = name(e.loop_kf_id);
      m.keyframe = e.current_kf_id;
      m.loop_keyframe = e.loop_kf_id;
      m.matches = e.matches;
      m.transform = edge_slam::transform_to_message(e.T_into_from, ros::Time(), "", "").transform;
      merge_pub_.publish(m);
    }
    publish_world_frames();
  }

  bool on_status(edge_slam_msgs::GetEdgeStatus::Request&, edge_slam_msgs::GetEdgeStatus::Response& res) {
    fill(res, *system_, 0);
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
    publish_merges();
    stats_pub_.publish(edge_slam::to_message(system_->stats(), "edge", ros::Time::now()));
    system_->write_outputs();
  }

  std::unique_ptr<edge_slam::EdgeSystem> system_;  // set in onInit, before any callback
  std::string map_frame_;
  std::vector<std::string> mobiles_;  // empty: one un-namespaced mobile
  struct Robot {
    ros::Publisher update_pub, ack_pub;
    ros::Subscriber keyframe_sub, frame_sub, floor_sub;
    ros::ServiceServer status_srv;  // /<robot>/edge_slam/edge_status: ~status for this robot
  };
  std::vector<Robot> robots_;  // index = robot index; filled in onInit, before any callback
  edge_slam::MapDisplay display_;
  ros::Publisher path_pub_, loop_pub_, stats_pub_, merge_pub_;
  tf2_ros::StaticTransformBroadcaster tf_static_;
  std::vector<std::optional<Eigen::Isometry3d>> world_frames_sent_;  // per robot, as last sent on /tf_static
  ros::ServiceServer status_srv_, save_srv_, load_srv_;
  std::unique_ptr<edge_slam::PeriodicSchedule> update_schedule_;  // touched by update_timer_'s callback only
  ros::WallTimer update_timer_, display_timer_, stats_timer_, ack_timer_, progress_timer_, checkpoint_timer_;
};

}  // namespace edge_slam_edge

PLUGINLIB_EXPORT_CLASS(edge_slam_edge::EdgeNodelet, nodelet::Nodelet)
