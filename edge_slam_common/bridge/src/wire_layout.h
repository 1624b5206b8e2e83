// A walk over the serialized bytes of KeyFrame, Frame and MapUpdate that checks every array
// length against the bytes actually present (and the receiver's limits) before roscpp
// deserializes them: roscpp resizes a vector to the length field *before* it checks the
// buffer, so 16 bytes claiming 4 G elements would allocate gigabytes. The walk mirrors the
// .msg field order; test_bridge_wire_layout pins it to the messages' MD5 sums.
#pragma once
#include <edge_slam/io/keypoint_coding.h>
#include <edge_slam_bridge/message_conversion.h>

#include <cstdint>
#include <cstring>
#include <string>

namespace edge_slam {
namespace wire {

class Walker {
 public:
  Walker(const uint8_t* data, size_t size) : at_(data), left_(size) {}

  // `bytes` fixed bytes (scalars, fixed arrays, nested fixed messages).
  bool fixed(size_t bytes, const char* field) {
    if (bytes > left_) return fail(std::string(field) + ": message truncated");
    at_ += bytes;
    left_ -= bytes;
    return true;
  }
  // A variable-length array of `element_bytes` elements, at most `max_count` of them.
  bool array(size_t element_bytes, size_t max_count, const char* field, uint32_t* count_out = nullptr) {
    uint32_t count = 0;
    if (!read_count(field, count)) return false;
    if (count > max_count)
      return fail(std::string(field) + ": " + std::to_string(count) + " elements, limit " + std::to_string(max_count));
    if (count_out) *count_out = count;
    return fixed(static_cast<size_t>(count) * element_bytes, field);
  }
  // The length prefix of an array of variable-size elements; each still needs >= min_bytes.
  bool count(size_t min_element_bytes, size_t max_count, const char* field, uint32_t& count) {
    if (!read_count(field, count)) return false;
    if (count > max_count || static_cast<size_t>(count) * min_element_bytes > left_)
      return fail(std::string(field) + ": " + std::to_string(count) + " elements do not fit the message");
    return true;
  }
  bool done() const { return left_ == 0; }
  size_t left() const { return left_; }
  const std::string& error() const { return error_; }
  bool fail(std::string why) {
    if (error_.empty()) error_ = std::move(why);
    return false;
  }
  bool fail_within(const std::string& where) {
    error_ = where + ": " + error_;
    return false;
  }

 private:
  bool read_count(const char* field, uint32_t& count) {
    if (left_ < 4) return fail(std::string(field) + ": message truncated");
    std::memcpy(&count, at_, 4);  // ROS serialization is little-endian, as is every target we build for
    at_ += 4;
    left_ -= 4;
    return true;
  }
  const uint8_t* at_;
  size_t left_;
  std::string error_;
};

// Camera + packed features, shared by KeyFrame and Frame (same fields, same order).
inline bool walk_camera_and_features(Walker& w, const MessageLimits& l) {
  return w.array(1, l.max_camera_name, "camera_name") && w.fixed(4 * 8 + 8 + 4 + 2 + 2, "intrinsics..height") &&
         w.array(1, max_keypoint_block_bytes(l.max_keypoints), "keypoints") &&
         w.array(1, 32 * l.max_keypoints, "descriptors");
}

inline bool walk_frame(Walker& w, const MessageLimits& l) {
  return w.fixed(1 + 8 + 4 + 8 + 8, "version..created_wall") && walk_camera_and_features(w, l);
}

// Smallest serialized KeyFrame: fixed fields plus 4-byte length prefixes of its 13 arrays/strings.
inline constexpr size_t kMinKeyFrameBytes =
    (1 + 8 + 4 + 4 + 8 + 8 + 1 + 56) + (32 + 8 + 4 + 2 + 2) + 4 + 8 + 4 + 4 + 13 * 4;

inline bool walk_keyframe(Walker& w, const MessageLimits& l) {
  return w.fixed(1 + 8 + 4 + 4 + 8 + 8 + 1 + 56, "version..pose") && walk_camera_and_features(w, l) &&
         w.array(1, (l.max_keypoints + 7) / 8, "obs_kp_mask") && w.array(4, l.max_keypoints, "obs_point_id") &&
         w.array(1, 11 + 4 * l.max_keypoints, "obs_point_id_packed") &&
         w.array(1, (l.max_keypoints + 7) / 8, "new_point_kp_mask") && w.fixed(4, "new_point_first_id") &&
         w.array(4, l.max_new_points, "new_point_id") && w.array(4, 3 * l.max_new_points, "new_point_xyz") && w.fixed(8, "decision counts") && w.fixed(4, "parent_id") &&
         w.array(4, l.max_covisibility, "covis_ids") && w.array(2, l.max_covisibility, "covis_weights") &&
         w.fixed(4, "refuted_first_id") && w.array(1, 4 * l.max_refuted_points, "refuted_mask") &&
         w.array(4, l.max_refuted_points, "refuted_point_ids");
}

inline bool walk_map_update(Walker& w, const MessageLimits& l) {
  if (!w.fixed(1 + 1 + 8 + 4 + 8 + 8 + 8, "version..last_keyframe_seq")) return false;
  uint32_t keyframes = 0;
  if (!w.count(kMinKeyFrameBytes, l.max_keyframes_per_update, "keyframes", keyframes)) return false;
  for (uint32_t i = 0; i < keyframes; ++i)
    if (!walk_keyframe(w, l)) return w.fail_within("keyframes[" + std::to_string(i) + "]");
  const size_t n = l.max_points_per_update;
  return w.array(4, n, "points.ids") && w.array(4, 3 * n, "points.positions") &&
         w.array(1, 32 * n, "points.descriptors") && w.array(4, 3 * n, "points.normals") &&
         w.array(4, 2 * n, "points.distances") && w.array(4, n, "points.ref_keyframe_ids");
}

}  // namespace wire
}  // namespace edge_slam
