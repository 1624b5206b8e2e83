// KeyFrameAck (module/keyframe_delivery.h) <-> edge_slam_msgs/KeyFrameAck: plain fields, no checks
// needed (any values are a valid acknowledgement; an old one changes nothing).
#pragma once
#include <edge_slam/module/keyframe_delivery.h>
#include <edge_slam_msgs/KeyFrameAck.h>

namespace edge_slam {

inline edge_slam_msgs::KeyFrameAck to_message(const KeyFrameAck& a) {
  edge_slam_msgs::KeyFrameAck m;
  m.boot_id = a.boot_id;
  m.received_seq = a.received_seq;
  m.durable_seq = a.durable_seq;
  m.persistent = a.persistent;
  m.mapped_seq = a.mapped_seq;
  m.mapper_busy_elsewhere = a.mapper_busy_elsewhere;
  return m;
}

inline KeyFrameAck from_message(const edge_slam_msgs::KeyFrameAck& m) {
  KeyFrameAck a;
  a.boot_id = m.boot_id;
  a.received_seq = m.received_seq;
  a.durable_seq = m.durable_seq;
  a.persistent = m.persistent;
  a.mapped_seq = m.mapped_seq;
  a.mapper_busy_elsewhere = m.mapper_busy_elsewhere;
  return a;
}

}  // namespace edge_slam
