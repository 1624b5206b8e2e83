// Bytes -> edge_slam_msgs with the array lengths checked first (see wire_layout.h): a receiver
// that deserializes itself (a ShapeShifter subscription, a bag, a fuzzer) gets a DecodeStatus
// instead of a multi-gigabyte allocation or a ros::serialization exception. On success the
// message still needs from_message(), which checks the field values.
#pragma once
#include <edge_slam_bridge/message_conversion.h>

#include <cstdint>

namespace edge_slam {

DecodeStatus deserialize_checked(const uint8_t* data, size_t size, edge_slam_msgs::KeyFrame& out,
                                 const MessageLimits& limits = MessageLimits());
DecodeStatus deserialize_checked(const uint8_t* data, size_t size, edge_slam_msgs::Frame& out,
                                 const MessageLimits& limits = MessageLimits());
DecodeStatus deserialize_checked(const uint8_t* data, size_t size, edge_slam_msgs::MapUpdate& out,
                                 const MessageLimits& limits = MessageLimits());

}  // namespace edge_slam
