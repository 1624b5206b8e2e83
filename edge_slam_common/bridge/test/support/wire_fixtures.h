// Valid wire messages made in code, for the bridge tests and the fuzzers' seed corpora:
// a KeyFrame with observations, new points and links; a Frame; a MapUpdate whose KeyFrames
// observe its points and form a spanning-tree chain.
#pragma once
#include <edge_slam/camera/pinhole_camera.h>
#include <edge_slam/io/point_id_coding.h>
#include <edge_slam_bridge/message_conversion.h>
#include <ros/serialization.h>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace edge_slam {
namespace fixtures {

// A message as it travels: its ROS serialization.
template <class Msg>
std::vector<uint8_t> serialized(const Msg& msg) {
  std::vector<uint8_t> out(ros::serialization::serializationLength(msg));
  ros::serialization::OStream stream(out.data(), static_cast<uint32_t>(out.size()));
  ros::serialization::serialize(stream, msg);
  return out;
}

// The observed point ids as the plain list (the sender packs them when that is smaller), for
// tests that change one id.
inline void list_observed_ids(edge_slam_msgs::KeyFrame& m) {
  if (m.obs_point_id_packed.empty()) return;
  size_t marked = 0;
  for (uint8_t byte : m.obs_kp_mask) marked += static_cast<size_t>(__builtin_popcount(byte));
  std::string error;
  if (!decode_point_ids(m.obs_point_id_packed.data(), m.obs_point_id_packed.size(), marked, m.obs_point_id, error))
    throw std::logic_error("list_observed_ids: " + error);
  m.obs_point_id_packed.clear();
}

inline CameraRecord camera() { return {"synthetic_room", 525, 525, 319.5, 239.5, 40.0, 3.05f, 640, 480}; }

// The receiver's configured camera that camera() describes.
inline PinholeCamera pinhole_camera() {
  const CameraRecord r = camera();
  PinholeCamera p;
  p.name = r.name;
  p.width = r.width;
  p.height = r.height;
  p.fx = r.fx;
  p.fy = r.fy;
  p.cx = r.cx;
  p.cy = r.cy;
  p.bf = r.bf;
  p.th_depth = r.th_depth;
  return p;
}

inline FeatureRecord features(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> ux(0.f, 639.f), uy(0.f, 479.f), ua(0.f, 359.9f), ud(0.4f, 8.f);
  FeatureRecord f;
  f.descriptors.create(static_cast<int>(n), 32, CV_8U);
  for (size_t i = 0; i < n; ++i) {
    f.keypoints.emplace_back(ux(rng), uy(rng), 31.f, ua(rng), 0.f, static_cast<int>(i % 8));
    f.depth.push_back(i % 5 == 0 ? 0.f : ud(rng));
    for (int b = 0; b < 32; ++b) f.descriptors.at<uint8_t>(static_cast<int>(i), b) = rng() & 0xFF;
  }
  return f;
}

// KeyFrame `id` observing points first_point + [0, n_obs) and creating n_new points.
inline KeyFrameRecord keyframe(uint32_t id, size_t n_features, size_t n_obs, size_t n_new, uint32_t first_point = 1000) {
  std::mt19937 rng(id + 1);
  KeyFrameRecord r;
  r.seq = id + 1;
  r.id = id;
  r.frame_id = 10 * id;
  r.stamp = 1305031102.0 + id;
  r.T_wc.linear() = Eigen::AngleAxisd(0.1 * id, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  r.T_wc.translation() = Eigen::Vector3d(0.1 * id, -0.2, 1.3);
  r.camera = camera();
  r.features = features(n_features, rng);
  for (size_t i = 0; i < n_obs; ++i) r.observations.emplace_back(static_cast<uint32_t>(i), first_point + i);
  for (size_t i = 0; i < n_new; ++i)
    r.new_points.push_back({static_cast<uint32_t>(50000 + 1000 * id + i), static_cast<uint32_t>(n_obs + i),
                            Eigen::Vector3f(0.1f * i, 1.f, 2.f)});
  r.parent_id = id > 0 ? id - 1 : kNoId;
  if (id > 0) r.covisibility = {{id - 1, 40}};
  if (id > 0) r.refuted_points = {40000 + 1000 * id, 40001 + 1000 * id};  // two of the previous KeyFrames' points
  return r;
}

inline FrameRecord frame(size_t n_features) {
  std::mt19937 rng(99);
  FrameRecord r;
  r.seq = 5;
  r.id = 321;
  r.stamp = 1305031110.5;
  r.camera = camera();
  r.features = features(n_features, rng);
  return r;
}

inline MapUpdateRecord map_update(uint32_t keyframes, size_t features, size_t points) {
  MapUpdateRecord u;
  u.seq = 3;
  u.last_keyframe_seq = keyframes;
  for (uint32_t k = 0; k < keyframes; ++k) u.keyframes.push_back(keyframe(k, features, points, 0));
  for (uint32_t i = 0; i < points; ++i) {
    MapPointRecord p;
    p.id = 1000 + i;
    p.position = {0.01f * i, 1, 2};
    p.normal = {0, 0, -1};
    p.descriptor.fill(static_cast<uint8_t>(i));
    p.min_distance = 0.5f;
    p.max_distance = 4.f;
    p.ref_keyframe_id = 0;
    u.points.push_back(p);
  }
  return u;
}

}  // namespace fixtures
}  // namespace edge_slam
