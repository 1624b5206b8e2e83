// Bits packed least significant first within each byte, and their bounds-checked reader: the
// keypoint and point-id blocks of KeyFrame messages (keypoint_coding.h, point_id_coding.h).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace edge_slam {

inline uint32_t bits_for(uint32_t max_value) {
  uint32_t bits = 0;
  while (bits < 32 && (max_value >> bits) != 0) ++bits;
  return bits;
}

// Bits, least significant first within each byte.
class BitWriter {
 public:
  explicit BitWriter(std::vector<uint8_t>& out) : out_(out) {}
  void put(uint32_t value, uint32_t bits) {
    for (uint32_t b = 0; b < bits; ++b) put_bit((value >> b) & 1u);
  }
  void put_ones_then_zero(uint32_t ones) {
    for (uint32_t i = 0; i < ones; ++i) put_bit(1);
    put_bit(0);
  }
  void put_bit(uint32_t bit) {
    if (used_ == 0) out_.push_back(0);
    if (bit) out_.back() |= static_cast<uint8_t>(1u << used_);
    used_ = (used_ + 1) & 7;
  }

 private:
  std::vector<uint8_t>& out_;
  uint32_t used_ = 0;
};

class BitReader {
 public:
  BitReader(const uint8_t* data, size_t size) : data_(data), bits_(size * 8) {}
  bool get(uint32_t bits, uint32_t& value) {
    if (bits > bits_ - at_) return false;
    value = 0;
    for (uint32_t b = 0; b < bits; ++b, ++at_) value |= ((data_[at_ >> 3] >> (at_ & 7)) & 1u) << b;
    return true;
  }
  // Ones up to the first zero, at most `limit` of them (then no zero follows).
  bool count_ones(uint32_t limit, uint32_t& ones) {
    ones = 0;
    uint32_t bit = 0;
    while (ones < limit) {
      if (!get(1, bit)) return false;
      if (!bit) return true;
      ++ones;
    }
    return true;
  }
  // The rest of the last byte is padding and must be zero.
  bool only_zero_padding_left() const {
    if (bits_ - at_ >= 8) return false;
    for (size_t b = at_; b < bits_; ++b)
      if ((data_[b >> 3] >> (b & 7)) & 1u) return false;
    return true;
  }

 private:
  const uint8_t* data_;
  size_t bits_;
  size_t at_ = 0;
};

}  // namespace edge_slam
