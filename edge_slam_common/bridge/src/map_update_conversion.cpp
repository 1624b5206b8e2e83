// MapUpdateRecord <-> edge_slam_msgs::MapUpdate.
#include <edge_slam_bridge/message_conversion.h>

#include <edge_slam/io/record_checks.h>
#include <ros/serialization.h>

#include <cstring>

namespace edge_slam {

edge_slam_msgs::MapUpdate to_message(const MapUpdateRecord& r) {
  edge_slam_msgs::MapUpdate msg;
  msg.version = edge_slam_msgs::MapUpdate::FORMAT_VERSION;
  msg.kind = static_cast<uint8_t>(r.kind);
  msg.seq = r.seq;
  msg.request_frame_id = r.request_frame_id;
  msg.build_start = ros::Time(r.build_start);
  msg.publish_stamp = ros::Time(r.publish_stamp);
  msg.last_keyframe_seq = r.last_keyframe_seq;
  msg.keyframes.reserve(r.keyframes.size());
  for (const KeyFrameRecord& kf : r.keyframes) msg.keyframes.push_back(to_message(kf));
  auto& pts = msg.points;
  const size_t n = r.points.size();
  pts.ids.resize(n);
  pts.positions.resize(3 * n);
  pts.descriptors.resize(32 * n);
  pts.normals.resize(3 * n);
  pts.distances.resize(2 * n);
  pts.ref_keyframe_ids.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const MapPointRecord& p = r.points[i];
    pts.ids[i] = p.id;
    for (int k = 0; k < 3; ++k) {
      pts.positions[3 * i + k] = p.position[k];
      pts.normals[3 * i + k] = p.normal[k];
    }
    std::memcpy(&pts.descriptors[32 * i], p.descriptor.data(), 32);
    pts.distances[2 * i] = p.min_distance;
    pts.distances[2 * i + 1] = p.max_distance;
    pts.ref_keyframe_ids[i] = p.ref_keyframe_id;
  }
  return msg;
}

DecodeStatus from_message(const edge_slam_msgs::MapUpdate& msg, MapUpdateRecord& out,
                          const MessageLimits& limits) {
  if (msg.version != edge_slam_msgs::MapUpdate::FORMAT_VERSION)
    return DecodeStatus::failure("MapUpdate version " + std::to_string(msg.version) + ", expected " +
                                 std::to_string(edge_slam_msgs::MapUpdate::FORMAT_VERSION));
  if (msg.kind > edge_slam_msgs::MapUpdate::KIND_RELOCALIZATION)
    return DecodeStatus::failure("MapUpdate kind " + std::to_string(msg.kind) + " is unknown");
  if (ros::serialization::serializationLength(msg) > limits.max_message_bytes)
    return DecodeStatus::failure("MapUpdate exceeds " + std::to_string(limits.max_message_bytes) + " bytes");
  if (msg.keyframes.size() > limits.max_keyframes_per_update)
    return DecodeStatus::failure("MapUpdate holds too many KeyFrames: " + std::to_string(msg.keyframes.size()));
  const auto& pts = msg.points;
  const size_t n = pts.ids.size();
  if (n > limits.max_points_per_update)
    return DecodeStatus::failure("MapUpdate holds too many points: " + std::to_string(n));
  if (pts.positions.size() != 3 * n || pts.descriptors.size() != 32 * n || pts.normals.size() != 3 * n ||
      pts.distances.size() != 2 * n || pts.ref_keyframe_ids.size() != n)
    return DecodeStatus::failure("MapUpdate point arrays disagree with " + std::to_string(n) +
                                 " ids (expected 3 positions, 32 descriptor bytes, 3 normals, 2 distances, "
                                 "1 reference KeyFrame per point)");
  MapUpdateRecord r;
  r.kind = static_cast<MapUpdateKind>(msg.kind);
  r.seq = msg.seq;
  r.request_frame_id = msg.request_frame_id;
  r.build_start = msg.build_start.toSec();
  r.publish_stamp = msg.publish_stamp.toSec();
  r.last_keyframe_seq = msg.last_keyframe_seq;
  r.keyframes.resize(msg.keyframes.size());
  for (size_t i = 0; i < msg.keyframes.size(); ++i) {
    DecodeStatus s = from_message(msg.keyframes[i], r.keyframes[i], limits);
    if (!s.ok) return DecodeStatus::failure("MapUpdate keyframes[" + std::to_string(i) + "]: " + s.error);
  }
  r.points.resize(n);
  for (size_t i = 0; i < n; ++i) {
    MapPointRecord& p = r.points[i];
    p.id = pts.ids[i];
    for (int k = 0; k < 3; ++k) {
      p.position[k] = pts.positions[3 * i + k];
      p.normal[k] = pts.normals[3 * i + k];
    }
    std::memcpy(p.descriptor.data(), &pts.descriptors[32 * i], 32);
    p.min_distance = pts.distances[2 * i];
    p.max_distance = pts.distances[2 * i + 1];
    p.ref_keyframe_id = pts.ref_keyframe_ids[i];
    if (p.id == kNoId) return DecodeStatus::failure("MapUpdate point with the reserved id at " + std::to_string(i));
    if (!p.position.allFinite() || !p.normal.allFinite() || !std::isfinite(p.min_distance) ||
        !std::isfinite(p.max_distance))
      return DecodeStatus::failure("MapUpdate point " + std::to_string(p.id) + " has non-finite values");
  }
  if (std::string problem = map_update_record_problem(r); !problem.empty())
    return DecodeStatus::failure("MapUpdate: " + problem);
  out = std::move(r);
  return {};
}

}  // namespace edge_slam
