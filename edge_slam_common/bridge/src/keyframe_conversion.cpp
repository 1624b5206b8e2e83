// KeyFrameRecord <-> edge_slam_msgs::KeyFrame.
#include <edge_slam_bridge/message_conversion.h>

#include <edge_slam/io/new_point_position.h>
#include <edge_slam/io/point_id_coding.h>
#include <edge_slam/io/record_checks.h>
#include <edge_slam_bridge/pose_conversion.h>
#include <ros/serialization.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "feature_packing.h"

namespace edge_slam {
namespace {

// A set of keypoints as one bit per keypoint (bit i % 8 of byte i / 8), ceil(n / 8) bytes, or
// none when the set is empty (format 5): a KeyFrame names hundreds of its 1000 keypoints, and a
// bit each costs less than a 2-byte index each. Indices out of range are left out (the caller's
// counts then disagree with the mask, and the receiver refuses the message).
// How many bits a mask sets: a list that has a repeat, or an entry the mask cannot name, sets
// fewer bits than it has entries.
size_t bits_set(const std::vector<uint8_t>& mask) {
  size_t set = 0;
  for (uint8_t b : mask) set += static_cast<size_t>(__builtin_popcount(b));
  return set;
}

std::vector<uint8_t> keypoint_mask(const std::vector<uint32_t>& indices, size_t n) {
  std::vector<uint8_t> mask;
  if (indices.empty()) return mask;
  mask.assign((n + 7) / 8, 0);
  for (uint32_t i : indices)
    if (i < n) mask[i / 8] |= static_cast<uint8_t>(1u << (i % 8));
  return mask;
}

// The set bits of a keypoint mask, in increasing order; fails on a wrong length or a bit past n.
DecodeStatus keypoints_of_mask(const std::vector<uint8_t>& mask, size_t n, const char* field,
                               std::vector<uint32_t>& out) {
  out.clear();
  if (mask.empty()) return {};
  if (mask.size() != (n + 7) / 8)
    return DecodeStatus::failure(std::string(field) + " has " + std::to_string(mask.size()) + " bytes, expected " +
                                 std::to_string((n + 7) / 8) + " (one bit per keypoint) or none");
  if (n % 8 != 0 && (mask.back() >> (n % 8)) != 0)
    return DecodeStatus::failure(std::string(field) + " marks a keypoint past the " + std::to_string(n) + " keypoints");
  for (size_t i = 0; i < n; ++i)
    if (mask[i / 8] & (1u << (i % 8))) out.push_back(static_cast<uint32_t>(i));
  return {};
}

// The refuted ids as a bit mask over [first, last] when that takes fewer bytes than the list
// (4 per id): the mobile's ids count up KeyFrame by KeyFrame, so the few hundred it refutes at
// a KeyFrame lie within the last KeyFrames' blocks, a bit each against 4 bytes.
void pack_refuted_points(const std::vector<uint32_t>& ids, edge_slam_msgs::KeyFrame& msg) {
  if (ids.empty()) return;
  const auto [lo, hi] = std::minmax_element(ids.begin(), ids.end());
  const uint64_t span = uint64_t{*hi} - *lo + 1;
  if ((span + 7) / 8 >= 4 * uint64_t{ids.size()}) {
    msg.refuted_point_ids = ids;
    return;
  }
  msg.refuted_first_id = *lo;
  msg.refuted_mask.assign((span + 7) / 8, 0);
  for (uint32_t id : ids) msg.refuted_mask[(id - *lo) / 8] |= static_cast<uint8_t>(1u << ((id - *lo) % 8));
  // A repeated id (an invalid record) would vanish in the mask: keep the list, the receiver refuses it.
  if (bits_set(msg.refuted_mask) != ids.size()) {
    msg.refuted_first_id = 0;
    msg.refuted_mask.clear();
    msg.refuted_point_ids = ids;
  }
}

DecodeStatus unpack_refuted_points(const edge_slam_msgs::KeyFrame& msg, const MessageLimits& limits,
                                   std::vector<uint32_t>& out) {
  const auto too_many = [&](size_t n) {
    return DecodeStatus::failure("too many refuted points: " + std::to_string(n) + " (at most " +
                                 std::to_string(limits.max_refuted_points) + ")");
  };
  if (msg.refuted_mask.empty()) {
    if (msg.refuted_point_ids.size() > limits.max_refuted_points) return too_many(msg.refuted_point_ids.size());
    out = msg.refuted_point_ids;
    return {};
  }
  if (!msg.refuted_point_ids.empty())
    return DecodeStatus::failure("refuted points given both as refuted_mask and as refuted_point_ids");
  std::vector<uint32_t> ids;
  for (size_t i = 0; i < msg.refuted_mask.size() * 8; ++i) {
    if (!(msg.refuted_mask[i / 8] & (1u << (i % 8)))) continue;
    const uint64_t id = uint64_t{msg.refuted_first_id} + i;
    if (id >= kNoId) return DecodeStatus::failure("refuted_mask reaches the reserved refuted point id");
    if (ids.size() == limits.max_refuted_points) return too_many(ids.size() + 1);
    ids.push_back(static_cast<uint32_t>(id));
  }
  out = std::move(ids);
  return {};
}

}  // namespace

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
  const std::vector<WireKeypoint> sent = packing::pack_camera_and_features(r.camera, r.features, msg);
  const size_t n = sent.size();
  // Observations in keypoint order: the keypoints as a mask, the point ids in that order.
  std::vector<std::pair<uint32_t, uint32_t>> obs = r.observations;
  std::stable_sort(obs.begin(), obs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<uint32_t> obs_keypoints, obs_points;
  obs_keypoints.reserve(obs.size());
  obs_points.reserve(obs.size());
  for (const auto& [kp, point] : obs) {
    obs_keypoints.push_back(kp);
    obs_points.push_back(point);
  }
  msg.obs_kp_mask = keypoint_mask(obs_keypoints, n);
  // The ids bit-packed when that is smaller (format 6: ~17 bits an id on fr1 against 32), and
  // only when the mask names one keypoint per id: a record it cannot say keeps the list, whose
  // length then disagrees with the mask and the receiver refuses it.
  std::vector<uint8_t> packed = encode_point_ids(obs_points);
  if (bits_set(msg.obs_kp_mask) == obs_points.size() && packed.size() < 4 * obs_points.size())
    msg.obs_point_id_packed = std::move(packed);
  else
    msg.obs_point_id = std::move(obs_points);
  // New points in keypoint order, their sources as a bit mask (format 5): a mobile KeyFrame
  // makes hundreds, and a bit per keypoint costs less than a 2-byte index per point.
  std::vector<const NewPointRecord*> news;
  news.reserve(r.new_points.size());
  for (const NewPointRecord& p : r.new_points) news.push_back(&p);
  std::stable_sort(news.begin(), news.end(), [](const auto* a, const auto* b) { return a->kp_index < b->kp_index; });
  // Ids are left out when they count up from the first in keypoint order, as the mobile
  // allocates them. A record the mask cannot say (a source out of range or used twice) keeps its
  // ids, whose count then disagrees with the mask: the receiver refuses it as before.
  bool ids_implied = !news.empty();
  std::vector<uint32_t> sources;
  sources.reserve(news.size());
  for (size_t k = 0; k < news.size(); ++k) {
    const size_t i = news[k]->kp_index;
    const bool expressible = i < n && (k == 0 || i != news[k - 1]->kp_index);
    sources.push_back(static_cast<uint32_t>(i));
    ids_implied = ids_implied && expressible && uint64_t{news[0]->id} + k == news[k]->id && news[k]->id != kNoId;
  }
  msg.new_point_kp_mask = keypoint_mask(sources, n);
  if (ids_implied) {
    msg.new_point_first_id = news.front()->id;
  } else {
    for (const NewPointRecord* p : news) msg.new_point_id.push_back(p->id);
  }
  // The positions go only where the receiver could not compute them from the keypoints as it
  // will read them (io/new_point_position.h): all of them, or none.
  const bool positions_implied = std::all_of(news.begin(), news.end(), [&](const NewPointRecord* p) {
    const size_t k = p->kp_index;
    if (k >= n) return false;
    const auto at = back_project(r.camera, r.T_wc, packing::dequantize_pixel(sent[k].x),
                                 packing::dequantize_pixel(sent[k].y), packing::dequantize_depth(sent[k].depth));
    return at && (p->position.cast<double>() - *at).norm() <= kNewPointPositionTolerance;
  });
  if (!positions_implied)
    for (const NewPointRecord* p : news)
      msg.new_point_xyz.insert(msg.new_point_xyz.end(), {p->position.x(), p->position.y(), p->position.z()});
  msg.parent_id = r.parent_id;
  msg.tracked_points = r.tracked_points;
  msg.reference_points = r.reference_points;
  msg.tracked_close_points = r.tracked_close_points;
  msg.untracked_close_points = r.untracked_close_points;
  for (const auto& [kf, weight] : r.covisibility) {
    msg.covis_ids.push_back(kf);
    msg.covis_weights.push_back(static_cast<uint16_t>(std::min<uint32_t>(weight, 65535)));
  }
  pack_refuted_points(r.refuted_points, msg);
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

  std::vector<uint32_t> observed;
  s = keypoints_of_mask(msg.obs_kp_mask, n, "obs_kp_mask", observed);
  if (!s.ok) return s;
  std::vector<uint32_t> unpacked;
  if (!msg.obs_point_id_packed.empty()) {
    if (!msg.obs_point_id.empty())
      return DecodeStatus::failure("observations carry both obs_point_id and obs_point_id_packed");
    std::string error;
    if (!decode_point_ids(msg.obs_point_id_packed.data(), msg.obs_point_id_packed.size(), observed.size(), unpacked,
                          error))
      return DecodeStatus::failure("obs_kp_mask marks " + std::to_string(observed.size()) + " keypoints; " + error);
  }
  const std::vector<uint32_t>& point_ids = msg.obs_point_id_packed.empty() ? msg.obs_point_id : unpacked;
  if (observed.size() != point_ids.size())
    return DecodeStatus::failure("obs_kp_mask marks " + std::to_string(observed.size()) + " keypoints but obs_point_id has " +
                                 std::to_string(point_ids.size()) + " ids");
  r.observations.reserve(observed.size());
  for (size_t i = 0; i < observed.size(); ++i) {
    if (point_ids[i] == kNoId) return DecodeStatus::failure("observation of the reserved point id");
    r.observations.emplace_back(observed[i], point_ids[i]);
  }

  // The new points' sources: the set bits of the mask, in keypoint order.
  std::vector<uint32_t> sources;
  s = keypoints_of_mask(msg.new_point_kp_mask, n, "new_point_kp_mask", sources);
  if (!s.ok) return s;
  const size_t m = sources.size();
  if (m > limits.max_new_points) return DecodeStatus::failure("too many new points: " + std::to_string(m));
  const bool ids_implied = msg.new_point_id.empty();
  if (ids_implied && m > 0 && (msg.new_point_first_id == kNoId || uint64_t{msg.new_point_first_id} + m - 1 >= kNoId))
    return DecodeStatus::failure("new_point_first_id " + std::to_string(msg.new_point_first_id) + " + " +
                                 std::to_string(m) + " new points reaches the reserved id");
  // No positions: each is its source keypoint back-projected (io/new_point_position.h).
  const bool positions_implied = msg.new_point_xyz.empty();
  if ((!ids_implied && msg.new_point_id.size() != m) || (!positions_implied && msg.new_point_xyz.size() != 3 * m))
    return DecodeStatus::failure("new_point arrays disagree: new_point_kp_mask marks " + std::to_string(m) +
                                 ", ids " + std::to_string(msg.new_point_id.size()) + " (or none: counted from new_point_first_id), xyz " +
                                 std::to_string(msg.new_point_xyz.size()) +
                                 " (expected 3 per point, or none: back-projected from the keypoints' depth)");
  r.new_points.resize(m);
  for (size_t i = 0; i < m; ++i) {
    NewPointRecord& p = r.new_points[i];
    p.id = ids_implied ? msg.new_point_first_id + static_cast<uint32_t>(i) : msg.new_point_id[i];
    p.kp_index = sources[i];
    if (p.id == kNoId) return DecodeStatus::failure("new point with the reserved id");
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
  s = unpack_refuted_points(msg, limits, r.refuted_points);
  if (!s.ok) return s;

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
