// KeyFrameRecord <-> edge_slam_msgs::KeyFrame.
#include <edge_slam_bridge/message_conversion.h>

#include <edge_slam/io/new_point_position.h>
#include <edge_slam/io/record_checks.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <ros/serialization.h>

#include <algorithm>
#include <cmath>

#include "feature_packing.h"

namespace edge_slam {

edge_slam_msgs::KeyFrame to_message(const KeyFrameRecord& r) {
  edge_slam_msgs::KeyFrame msg;
  msg.version = edge_slam_msgs::KeyFrame::FORMAT_VERSION;
  msg.seq = r.seq;
  msg.id = r.id;
  msg.frame_id = r.frame_id;
  msg.stamp = ros::Time(r.stamp);
  msg.created_wall = r.created_wall;
  msg.reset = r.reset;
  msg.pose = pose_to_message(r.T_wc);
  packing::pack_camera_and_features(r.camera, r.features, msg);
  msg.obs_kp_index.reserve(r.observations.size());
  msg.obs_point_id.reserve(r.observations.size());
  for (const auto& [kp, point] : r.observations) {
    msg.obs_kp_index.push_back(static_cast<uint16_t>(kp));
    msg.obs_point_id.push_back(point);
  }
  // The positions go only where the receiver could not compute them from the keypoints as it
  // will read them (io/new_point_position.h): all of them, or none.
  const bool positions_implied = std::all_of(r.new_points.begin(), r.new_points.end(), [&](const NewPointRecord& p) {
    const size_t k = p.kp_index;
    if (k >= msg.kp_depth.size()) return false;
    const auto at = back_project(r.camera, r.T_wc, packing::dequantize_pixel(msg.kp_xy[2 * k]),
                                 packing::dequantize_pixel(msg.kp_xy[2 * k + 1]), packing::dequantize_depth(msg.kp_depth[k]));
    return at && (p.position.cast<double>() - *at).norm() <= kNewPointPositionTolerance;
  });
  for (const NewPointRecord& p : r.new_points) {
    msg.new_point_id.push_back(p.id);
    msg.new_point_kp_index.push_back(static_cast<uint16_t>(p.kp_index));
    if (!positions_implied)
      msg.new_point_xyz.insert(msg.new_point_xyz.end(), {p.position.x(), p.position.y(), p.position.z()});
  }
  msg.parent_id = r.parent_id;
  msg.tracked_points = r.tracked_points;
  msg.reference_points = r.reference_points;
  msg.tracked_close_points = r.tracked_close_points;
  msg.untracked_close_points = r.untracked_close_points;
  for (const auto& [kf, weight] : r.covisibility) {
    msg.covis_ids.push_back(kf);
    msg.covis_weights.push_back(static_cast<uint16_t>(std::min<uint32_t>(weight, 65535)));
  }
  msg.refuted_point_ids = r.refuted_points;
  return msg;
}

DecodeStatus from_message(const edge_slam_msgs::KeyFrame& msg, KeyFrameRecord& out,
                          const MessageLimits& limits) {
  if (msg.version != edge_slam_msgs::KeyFrame::FORMAT_VERSION)
    return DecodeStatus::failure("KeyFrame version " + std::to_string(msg.version) + ", expected " +
                                 std::to_string(edge_slam_msgs::KeyFrame::FORMAT_VERSION));
  if (msg.id == kNoId) return DecodeStatus::failure("KeyFrame id is the reserved 'no id' value");
  if (ros::serialization::serializationLength(msg) > limits.max_message_bytes)
    return DecodeStatus::failure("KeyFrame " + std::to_string(msg.id) + " exceeds " +
                                 std::to_string(limits.max_message_bytes) + " bytes");
  KeyFrameRecord r;
  if (!pose_from_message(msg.pose, r.T_wc))
    return DecodeStatus::failure("KeyFrame pose is not finite or its quaternion is not unit length");
  DecodeStatus s = packing::unpack_camera_and_features(msg, limits, r.camera, r.features);
  if (!s.ok) return DecodeStatus::failure("KeyFrame " + std::to_string(msg.id) + ": " + s.error);
  const size_t n = r.features.size();

  if (msg.obs_kp_index.size() != msg.obs_point_id.size())
    return DecodeStatus::failure("obs_kp_index and obs_point_id differ in length");
  if (msg.obs_kp_index.size() > n) return DecodeStatus::failure("more observations than keypoints");
  r.observations.reserve(msg.obs_kp_index.size());
  for (size_t i = 0; i < msg.obs_kp_index.size(); ++i) {
    if (msg.obs_kp_index[i] >= n)
      return DecodeStatus::failure("obs_kp_index[" + std::to_string(i) + "] = " +
                                   std::to_string(msg.obs_kp_index[i]) + " >= keypoints " + std::to_string(n));
    if (msg.obs_point_id[i] == kNoId) return DecodeStatus::failure("observation of the reserved point id");
    r.observations.emplace_back(msg.obs_kp_index[i], msg.obs_point_id[i]);
  }

  const size_t m = msg.new_point_id.size();
  if (m > limits.max_new_points) return DecodeStatus::failure("too many new points: " + std::to_string(m));
  // No positions: each is its source keypoint back-projected (io/new_point_position.h).
  const bool positions_implied = msg.new_point_xyz.empty();
  if (msg.new_point_kp_index.size() != m || (!positions_implied && msg.new_point_xyz.size() != 3 * m))
    return DecodeStatus::failure("new_point arrays disagree: ids " + std::to_string(m) + ", kp_index " +
                                 std::to_string(msg.new_point_kp_index.size()) + ", xyz " +
                                 std::to_string(msg.new_point_xyz.size()) +
                                 " (expected 3 per point, or none: back-projected from the keypoints' depth)");
  r.new_points.resize(m);
  for (size_t i = 0; i < m; ++i) {
    NewPointRecord& p = r.new_points[i];
    p.id = msg.new_point_id[i];
    p.kp_index = msg.new_point_kp_index[i];
    if (p.id == kNoId) return DecodeStatus::failure("new point with the reserved id");
    if (p.kp_index >= n) return DecodeStatus::failure("new_point_kp_index out of range at " + std::to_string(i));
    if (positions_implied) {
      const auto at = back_projected_keypoint(r, p.kp_index);
      if (!at)
        return DecodeStatus::failure("new point " + std::to_string(p.id) + " has no position and its keypoint " +
                                     std::to_string(p.kp_index) + " no depth to back-project");
      p.position = at->cast<float>();
    } else {
      p.position = {msg.new_point_xyz[3 * i], msg.new_point_xyz[3 * i + 1], msg.new_point_xyz[3 * i + 2]};
    }
    if (!p.position.allFinite()) return DecodeStatus::failure("new point " + std::to_string(p.id) + " is not finite");
  }

  if (msg.covis_ids.size() != msg.covis_weights.size())
    return DecodeStatus::failure("covis_ids and covis_weights differ in length");
  if (msg.covis_ids.size() > limits.max_covisibility) return DecodeStatus::failure("too many covisibility links");
  for (size_t i = 0; i < msg.covis_ids.size(); ++i) {
    if (msg.covis_ids[i] == kNoId || msg.covis_ids[i] == msg.id)
      return DecodeStatus::failure("covis_ids[" + std::to_string(i) + "] is the reserved id or the KeyFrame itself");
    r.covisibility.emplace_back(msg.covis_ids[i], msg.covis_weights[i]);
  }
  if (msg.parent_id == msg.id) return DecodeStatus::failure("KeyFrame " + std::to_string(msg.id) + " is its own parent");
  if (msg.refuted_point_ids.size() > limits.max_refuted_points)
    return DecodeStatus::failure("too many refuted points: " + std::to_string(msg.refuted_point_ids.size()) +
                                 " (at most " + std::to_string(limits.max_refuted_points) + ")");
  r.refuted_points = msg.refuted_point_ids;

  if (!std::isfinite(msg.created_wall)) return DecodeStatus::failure("created_wall is not finite");
  r.seq = msg.seq;
  r.id = msg.id;
  r.frame_id = msg.frame_id;
  r.stamp = msg.stamp.toSec();
  r.created_wall = msg.created_wall;
  r.reset = msg.reset;
  r.parent_id = msg.parent_id;
  r.tracked_points = msg.tracked_points;
  r.reference_points = msg.reference_points;
  r.tracked_close_points = msg.tracked_close_points;
  r.untracked_close_points = msg.untracked_close_points;
  // The remaining record-level rules (one point per keypoint, unique links, ranges) are the
  // core's, shared with every other way a record can arrive.
  if (std::string problem = keyframe_record_problem(r); !problem.empty()) return DecodeStatus::failure(problem);
  out = std::move(r);
  return {};
}

}  // namespace edge_slam
