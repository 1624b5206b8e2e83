// Quantisation of camera + features into the fields that KeyFrame.msg and Frame.msg share
// (same field names, hence templates), and their validated inverse.
#pragma once
#include <edge_slam/io/keypoint_coding.h>
#include <edge_slam/io/wire_records.h>
#include <edge_slam_bridge/message_conversion.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace edge_slam {
namespace packing {

constexpr float kPixelUnits = 8.0f;      // keypoint x, y: 1/8 pixel
constexpr float kDepthUnits = 4000.0f;   // keypoint depth: 1/4 mm
constexpr float kAngleUnits = 256.0f / 360.0f;

inline int16_t quantize_pixel(float v) {
  const float q = std::round(v * kPixelUnits);
  return static_cast<int16_t>(std::clamp(q, -32768.0f, 32767.0f));
}
inline uint16_t quantize_depth(float z) {
  if (!(z > 0.0f)) return 0;
  const float q = std::round(z * kDepthUnits);
  return q > 65535.0f ? 0 : static_cast<uint16_t>(q);  // beyond 16 m: treated as no depth
}
// What a receiver reads back (unpack_camera_and_features below, and the new points' check in
// keyframe_conversion.cpp, which must see exactly the receiver's values).
inline float dequantize_pixel(int16_t q) { return q / kPixelUnits; }
inline float dequantize_depth(uint16_t q) { return q / kDepthUnits; }
inline uint8_t quantize_angle(float deg) {
  if (!std::isfinite(deg)) return 0;
  float a = std::fmod(deg, 360.0f);
  if (a < 0) a += 360.0f;
  return static_cast<uint8_t>(static_cast<int>(std::round(a * kAngleUnits)) & 0xFF);
}

inline bool finite(double v) { return std::isfinite(v); }

// The keypoints as they travel: quantised (an octave above what the coding takes is clamped, as
// the 8-bit field did before; no extractor makes one).
inline std::vector<WireKeypoint> wire_keypoints(const FeatureRecord& f) {
  std::vector<WireKeypoint> wire(f.keypoints.size());
  for (size_t i = 0; i < wire.size(); ++i) {
    const cv::KeyPoint& kp = f.keypoints[i];
    wire[i].x = quantize_pixel(kp.pt.x);
    wire[i].y = quantize_pixel(kp.pt.y);
    wire[i].octave = static_cast<uint8_t>(std::clamp<int>(kp.octave, 0, kMaxWireOctave));
    wire[i].angle = quantize_angle(kp.angle);
    wire[i].depth = i < f.depth.size() ? quantize_depth(f.depth[i]) : 0;
  }
  return wire;
}

// Returns the keypoints as the receiver will read them.
template <class Msg>
std::vector<WireKeypoint> pack_camera_and_features(const CameraRecord& cam, const FeatureRecord& f, Msg& msg) {
  msg.camera_name = cam.name;
  msg.intrinsics = {cam.fx, cam.fy, cam.cx, cam.cy};
  msg.bf = cam.bf;
  msg.th_depth = cam.th_depth;
  msg.width = static_cast<uint16_t>(cam.width);
  msg.height = static_cast<uint16_t>(cam.height);
  const size_t n = f.keypoints.size();
  std::vector<WireKeypoint> wire = wire_keypoints(f);
  msg.keypoints = encode_keypoints(wire);
  msg.descriptors.resize(n * 32);
  if (n > 0 && f.descriptors.rows == static_cast<int>(n) && f.descriptors.cols == 32 &&
      f.descriptors.type() == CV_8U) {
    for (size_t i = 0; i < n; ++i)
      std::memcpy(&msg.descriptors[32 * i], f.descriptors.ptr<uint8_t>(static_cast<int>(i)), 32);
  }
  return wire;
}

template <class Msg>
DecodeStatus unpack_camera_and_features(const Msg& msg, const MessageLimits& limits,
                                        CameraRecord& cam, FeatureRecord& f) {
  if (msg.camera_name.size() > limits.max_camera_name)
    return DecodeStatus::failure("camera_name longer than " + std::to_string(limits.max_camera_name) + " bytes");
  for (int i = 0; i < 4; ++i)
    if (!finite(msg.intrinsics[i]))
      return DecodeStatus::failure("intrinsics[" + std::to_string(i) + "] is not finite");
  if (!(msg.intrinsics[0] > 0) || !(msg.intrinsics[1] > 0))
    return DecodeStatus::failure("intrinsics fx, fy must be > 0");
  if (!finite(msg.bf) || msg.bf < 0) return DecodeStatus::failure("bf must be finite and >= 0");
  if (!std::isfinite(msg.th_depth) || msg.th_depth < 0)
    return DecodeStatus::failure("th_depth must be finite and >= 0");
  if (msg.width == 0 || msg.height == 0 || msg.width > limits.max_image_side ||
      msg.height > limits.max_image_side)
    return DecodeStatus::failure("width/height must be in 1.." + std::to_string(limits.max_image_side));
  if (msg.descriptors.size() % 32 != 0)
    return DecodeStatus::failure("descriptors hold " + std::to_string(msg.descriptors.size()) +
                                 " bytes, not 32 per keypoint");
  const size_t n = msg.descriptors.size() / 32;
  if (n > limits.max_keypoints)
    return DecodeStatus::failure("too many keypoints: " + std::to_string(n) + " > " +
                                 std::to_string(limits.max_keypoints));
  std::vector<WireKeypoint> wire;
  std::string error;
  if (!decode_keypoints(msg.keypoints.data(), msg.keypoints.size(), n, wire, error))
    return DecodeStatus::failure(error);

  cam.name = msg.camera_name;
  cam.fx = msg.intrinsics[0];
  cam.fy = msg.intrinsics[1];
  cam.cx = msg.intrinsics[2];
  cam.cy = msg.intrinsics[3];
  cam.bf = msg.bf;
  cam.th_depth = msg.th_depth;
  cam.width = msg.width;
  cam.height = msg.height;
  f.keypoints.resize(n);
  f.depth.resize(n);
  for (size_t i = 0; i < n; ++i) {
    cv::KeyPoint& kp = f.keypoints[i];
    kp.pt.x = dequantize_pixel(wire[i].x);
    kp.pt.y = dequantize_pixel(wire[i].y);
    kp.octave = wire[i].octave;
    kp.angle = wire[i].angle / kAngleUnits;
    f.depth[i] = dequantize_depth(wire[i].depth);
  }
  f.descriptors.create(static_cast<int>(n), 32, CV_8U);
  if (n > 0) std::memcpy(f.descriptors.data, msg.descriptors.data(), 32 * n);
  return {};
}

}  // namespace packing
}  // namespace edge_slam
