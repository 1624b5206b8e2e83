// The mobile's two status services filled from the core (split/mobile_system.h): the map-update
// controller's counters (~map_update_status) and the KeyFrame delivery accounting (~delivery_status).
#pragma once
#include <edge_slam/split/mobile_system.h>
#include <edge_slam_msgs/GetDeliveryStatus.h>
#include <edge_slam_msgs/GetMapUpdateStatus.h>

namespace edge_slam_mobile {

inline void fill(edge_slam_msgs::GetMapUpdateStatus::Response& res, const edge_slam::MobileSystem& system,
                 const edge_slam::MobileSession& s) {
  using edge_slam::ImageProblem;
  const edge_slam::MapUpdateCounters c = s.update_counters();
  res.enabled = s.updates_enabled();
  res.received = c.received;
  res.accepted = c.accepted;
  res.rejected_controller = c.rejected_controller;
  res.rejected_initializing = c.rejected_initializing;
  res.rejected_redundant = c.rejected_redundant;
  res.rejected_keyframe_rate = c.rejected_keyframe_rate;
  res.rejected_not_lost = c.rejected_not_lost;
  res.rejected_invalid = c.rejected_invalid;
  res.relocalization_applied = c.relocalization_applied;
  res.local_map_keyframes = static_cast<uint32_t>(s.local_map_keyframes());
  res.local_map_peak = static_cast<uint32_t>(s.local_map_peak());
  res.local_map_cap = static_cast<uint32_t>(s.local_map_cap());
  res.local_map_points = static_cast<uint32_t>(s.local_map_points());
  for (const auto& kf : s.local_map()->keyframes()) res.local_map_ids.push_back(kf->id());
  res.images_rejected_stamp = static_cast<uint32_t>(system.images_rejected(ImageProblem::kStamp));
  res.images_rejected_encoding = static_cast<uint32_t>(system.images_rejected(ImageProblem::kEncoding));
  res.images_rejected_size = static_cast<uint32_t>(system.images_rejected(ImageProblem::kSize));
  res.images_rejected_depth = static_cast<uint32_t>(system.images_rejected(ImageProblem::kDepth));
  res.keyframes_created = static_cast<uint32_t>(s.keyframes_sent());
  res.time_constraint = s.time_constraint();
}

// Before tracking starts there is no session: nothing created, nothing sent.
inline void fill(edge_slam_msgs::GetDeliveryStatus::Response& res, edge_slam::MobileSystem& system,
                 edge_slam::MobileSession* s) {
  const edge_slam::DeliveryCounters c = system.sender().counters();
  res.created = s ? s->keyframe_ids_created().size() : 0;
  res.sent = c.sent;
  res.resent = c.resent;
  res.acknowledged = c.acknowledged;
  res.durable = c.durable;
  res.dropped_by_bound = c.dropped_by_bound;
  res.dropped_by_outbox = s ? s->outbox().evictions() : 0;
  res.queued = c.queued;
  res.edge_restarts = c.edge_restarts;
  res.seconds_since_ack = system.sender().seconds_since_ack(system.now());
  if (s) res.created_ids = s->keyframe_ids_created();
}

}  // namespace edge_slam_mobile
