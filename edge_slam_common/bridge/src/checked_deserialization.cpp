// Length-checked deserialization of the three wire messages.
#include <edge_slam_bridge/checked_deserialization.h>
#include <ros/serialization.h>

#include "wire_layout.h"

namespace edge_slam {
namespace {

template <class Msg, class Walk>
DecodeStatus deserialize_with(const uint8_t* data, size_t size, Msg& out, const MessageLimits& limits,
                              Walk walk, const char* type) {
  if (size > limits.max_message_bytes)
    return DecodeStatus::failure(std::string(type) + " of " + std::to_string(size) + " bytes exceeds the " +
                                 std::to_string(limits.max_message_bytes) + "-byte limit");
  wire::Walker w(data, size);
  if (!walk(w, limits)) return DecodeStatus::failure(std::string(type) + ": " + w.error());
  if (!w.done())
    return DecodeStatus::failure(std::string(type) + ": " + std::to_string(w.left()) + " trailing bytes");
  Msg msg;
  try {
    // IStream only reads; the const_cast is its interface, not a write.
    ros::serialization::IStream stream(const_cast<uint8_t*>(data), static_cast<uint32_t>(size));
    ros::serialization::deserialize(stream, msg);
  } catch (const std::exception& e) {
    return DecodeStatus::failure(std::string(type) + ": " + e.what());
  }
  out = std::move(msg);
  return {};
}

}  // namespace

DecodeStatus deserialize_checked(const uint8_t* data, size_t size, edge_slam_msgs::KeyFrame& out,
                                 const MessageLimits& limits) {
  return deserialize_with(data, size, out, limits, wire::walk_keyframe, "KeyFrame");
}
DecodeStatus deserialize_checked(const uint8_t* data, size_t size, edge_slam_msgs::Frame& out,
                                 const MessageLimits& limits) {
  return deserialize_with(data, size, out, limits, wire::walk_frame, "Frame");
}
DecodeStatus deserialize_checked(const uint8_t* data, size_t size, edge_slam_msgs::MapUpdate& out,
                                 const MessageLimits& limits) {
  return deserialize_with(data, size, out, limits, wire::walk_map_update, "MapUpdate");
}

}  // namespace edge_slam
