// FrameRecord <-> edge_slam_msgs::Frame (relocalization assistance).
#include <edge_slam_bridge/message_conversion.h>

#include <cmath>
#include <edge_slam/io/record_checks.h>

#include "feature_packing.h"

namespace edge_slam {

edge_slam_msgs::Frame to_message(const FrameRecord& r) {
  edge_slam_msgs::Frame msg;
  msg.version = edge_slam_msgs::Frame::FORMAT_VERSION;
  msg.seq = r.seq;
  msg.id = r.id;
  msg.stamp = ros::Time(r.stamp);
  msg.created_wall = r.created_wall;
  packing::pack_camera_and_features(r.camera, r.features, msg);
  return msg;
}

DecodeStatus from_message(const edge_slam_msgs::Frame& msg, FrameRecord& out, const MessageLimits& limits) {
  if (msg.version != edge_slam_msgs::Frame::FORMAT_VERSION)
    return DecodeStatus::failure("Frame version " + std::to_string(msg.version) + ", expected " +
                                 std::to_string(edge_slam_msgs::Frame::FORMAT_VERSION));
  FrameRecord r;
  DecodeStatus s = packing::unpack_camera_and_features(msg, limits, r.camera, r.features);
  if (!s.ok) return DecodeStatus::failure("Frame " + std::to_string(msg.id) + ": " + s.error);
  if (!std::isfinite(msg.created_wall))
    return DecodeStatus::failure("Frame " + std::to_string(msg.id) + ": created_wall is not finite");
  if (std::string problem = feature_record_problem(r.features); !problem.empty())
    return DecodeStatus::failure("Frame " + std::to_string(msg.id) + ": " + problem);
  r.seq = msg.seq;
  r.id = msg.id;
  r.stamp = msg.stamp.toSec();
  r.created_wall = msg.created_wall;
  out = std::move(r);
  return {};
}

}  // namespace edge_slam
