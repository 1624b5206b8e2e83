#pragma once
// The point ids a KeyFrame message's observations name (in keypoint order) as one bit-packed
// block instead of 4 bytes each (KeyFrame.msg format 6, `obs_point_id_packed`). Ids come from two
// allocators (util/robot_ids.h): the mobiles' below 2^31, the edge's from 2^31; a KeyFrame sees
// recent points of both, so each id is a class bit and its offset from its class's smallest id, in
// as many bits as that class's span needs (fr1: ~17 bits an id against 32). Lossless.
//
// Layout (little-endian):
//   uint8  coding                 kPointIdCoding (1)
//   uint32 low_base, uint8 low_bits     ids below 2^31: low_base + offset, offset in low_bits (0..31)
//   uint32 high_base, uint8 high_bits   ids from 2^31: high_base + offset, offset in high_bits (0..31)
//   bits, least significant first in each byte, per id in order: 1 class bit (1 = high), the offset
//   the last byte's unused bits are zero; nothing follows.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace edge_slam {

constexpr uint8_t kPointIdCoding = 1;
constexpr uint32_t kHighPointIds = 0x80000000u;

std::vector<uint8_t> encode_point_ids(const std::vector<uint32_t>& ids);

// Reads exactly `count` ids; false with `error` saying what was expected when the block is
// malformed, shorter or longer than they need, or an id falls outside its class.
bool decode_point_ids(const uint8_t* data, size_t size, size_t count, std::vector<uint32_t>& out, std::string& error);

}  // namespace edge_slam
