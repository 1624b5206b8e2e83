// The thin ROS bridge shared by the mobile and the edge: wire records <-> edge_slam_msgs.
// Outgoing records are quantised into the compact typed arrays of the messages; incoming
// messages are validated field by field before anything touches a map, so a malformed or
// oversized message is rejected with a reason instead of crashing the receiver.
#pragma once
#include <edge_slam/io/wire_records.h>
#include <edge_slam_msgs/Frame.h>
#include <edge_slam_msgs/KeyFrame.h>
#include <edge_slam_msgs/MapUpdate.h>

#include <string>

namespace edge_slam {

// Upper bounds a receiver accepts; anything larger is treated as corrupt.
struct MessageLimits {
  size_t max_keypoints = 8000;
  size_t max_new_points = 8000;
  size_t max_keyframes_per_update = 2000;
  size_t max_points_per_update = 2000000;
  size_t max_covisibility = 4000;
  size_t max_refuted_points = 20000;  // a Local-Map holds ~10^4 points; the refuted are a share of its newest
  size_t max_camera_name = 256;
  int max_image_side = 8192;
  size_t max_message_bytes = 256u << 20;  // serialized size
};

// Result of decoding: `ok` false means `error` says which field was wrong and what was expected.
struct DecodeStatus {
  bool ok = true;
  std::string error;
  static DecodeStatus failure(std::string why) { return {false, std::move(why)}; }
};

edge_slam_msgs::KeyFrame to_message(const KeyFrameRecord& record);
edge_slam_msgs::Frame to_message(const FrameRecord& record);
edge_slam_msgs::MapUpdate to_message(const MapUpdateRecord& record);

DecodeStatus from_message(const edge_slam_msgs::KeyFrame& msg, KeyFrameRecord& out,
                          const MessageLimits& limits = MessageLimits());
DecodeStatus from_message(const edge_slam_msgs::Frame& msg, FrameRecord& out,
                          const MessageLimits& limits = MessageLimits());
DecodeStatus from_message(const edge_slam_msgs::MapUpdate& msg, MapUpdateRecord& out,
                          const MessageLimits& limits = MessageLimits());

}  // namespace edge_slam
