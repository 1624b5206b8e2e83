// The edge's ~status service filled from the core (split/edge_system.h): one robot's counters,
// KeyFrame id accounting and delivery state, the whole Global-Map's size, the durability state.
#pragma once
#include <edge_slam/split/edge_system.h>
#include <edge_slam_msgs/GetEdgeStatus.h>

namespace edge_slam_edge {

inline void fill(edge_slam_msgs::GetEdgeStatus::Response& res, const edge_slam::EdgeSystem& system, int robot) {
  using Topic = edge_slam::EdgeSystem::Topic;
  const edge_slam::EdgeSession& session = system.session();
  const edge_slam::EdgeCounters c = session.counters(robot);
  res.received = static_cast<uint32_t>(c.received);
  res.inserted = static_cast<uint32_t>(c.inserted);
  res.duplicates = static_cast<uint32_t>(c.duplicates);
  res.rejected_condition1 = static_cast<uint32_t>(c.rejected_condition1);
  res.rejected_condition2 = static_cast<uint32_t>(c.rejected_condition2);
  res.invalid = static_cast<uint32_t>(c.invalid + system.malformed());
  res.malformed_keyframes = static_cast<uint32_t>(system.malformed(Topic::kKeyFrames));
  res.malformed_frames = static_cast<uint32_t>(system.malformed(Topic::kFrames));
  res.resets = static_cast<uint32_t>(c.resets);
  res.updates_sent = static_cast<uint32_t>(c.updates_built);
  res.relocalization_updates_sent = static_cast<uint32_t>(c.relocalization_updates_built);
  res.loops_closed = static_cast<uint32_t>(session.loops_closed());
  const auto map = session.global_map();
  res.global_map_keyframes = static_cast<uint32_t>(map->num_keyframes());
  res.global_map_points = static_cast<uint32_t>(map->num_map_points());
  const edge_slam::KeyFrameAccount a = session.keyframe_account(robot);
  res.inserted_ids = a.inserted;
  res.culled_ids = a.culled;
  res.global_map_ids = a.in_map;
  res.received_ids = a.received;
  res.received_seq = c.received_seq;
  res.durable_seq = system.durability().durable_seq(robot);
  res.boot_id = system.durability().boot_id();
  res.checkpoints = static_cast<uint32_t>(system.durability().checkpoints());
}

}  // namespace edge_slam_edge
