#pragma once
// The keypoints of a KeyFrame or Frame message as one bit-packed block (KeyFrame.msg format 6,
// Frame.msg format 2). Lossless on the quantised values the messages always carried (x, y in
// 1/8 pixel, pyramid level, angle in 360/256 degrees, depth in 1/4 mm): the same values come
// back. Why: after format 5 a fr1 KeyFrame was 42.5 KB, 40 of it the 1000 keypoints at 40 bytes,
// 8 of them these fields at fixed width (issue #14's upload target). Here they cost ~5.5 bytes:
//  - the pyramid level as runs (the extractor emits level by level: a few runs per message);
//  - y as the difference from the previous keypoint's y, Rice-coded with a parameter per run
//    (the extractor emits a level's keypoints in row order, so the differences are small);
//  - x above the message's smallest x, depth in as many bits as the message's largest depth
//    needs, angle in 8 bits.
// Any order of keypoints can be coded (a level may come back in several runs, a y may go down);
// it only costs more bits.
//
// Layout (little-endian):
//   uint8  coding            kKeypointCoding (1)
//   int16  x_min             smallest x
//   uint8  x_bits            0..16: bits of (x - x_min)
//   uint8  depth_bits        0..16: bits of depth (0 = no depth)
//   uint16 runs              then per run: uint8 octave (0..31), uint16 count (>= 1), uint8 k (0..16)
//   bits, least significant first in each byte, per keypoint in order:
//     y: zigzag(y - previous y; the first keypoint's previous y is 0) as q = v >> k ones, a zero and
//        the k low bits; when q >= kRiceEscape: kRiceEscape ones and v in 17 bits
//     x - x_min in x_bits, angle in 8 bits, depth in depth_bits
//   the last byte's unused bits are zero; nothing follows.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace edge_slam {

constexpr uint8_t kKeypointCoding = 1;
constexpr uint32_t kRiceEscape = 24;

// One keypoint as it travels (the bridge's quantisation, edge_slam_bridge feature_packing.h).
struct WireKeypoint {
  int16_t x = 0;       // 1/8 pixel
  int16_t y = 0;       // 1/8 pixel
  uint8_t octave = 0;  // pyramid level, 0..31
  uint8_t angle = 0;   // 360/256 degrees
  uint16_t depth = 0;  // 1/4 mm, 0 = none
  bool operator==(const WireKeypoint& o) const {
    return x == o.x && y == o.y && octave == o.octave && angle == o.angle && depth == o.depth;
  }
};

// Octaves above this cannot be coded (nor decoded): a receiver refuses them.
constexpr uint8_t kMaxWireOctave = 31;

// The block for `keypoints`; throws std::invalid_argument for an octave above kMaxWireOctave.
std::vector<uint8_t> encode_keypoints(const std::vector<WireKeypoint>& keypoints);

// Reads exactly `count` keypoints from the block; false with `error` saying what was expected
// when the block is malformed, shorter or longer than they need, or codes another count.
bool decode_keypoints(const uint8_t* data, size_t size, size_t count, std::vector<WireKeypoint>& out,
                      std::string& error);

// The largest block `count` keypoints can take (at most `count` runs): the receiver's bound.
size_t max_keypoint_block_bytes(size_t count);

}  // namespace edge_slam
