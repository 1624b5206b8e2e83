// Hamming distance between two 256-bit ORB descriptors (32 bytes each).
// Shared by matching, the BoW vocabulary and map point descriptor selection.
#pragma once
#include <cstdint>
#include <cstring>

namespace edge_slam {

constexpr int kDescriptorBytes = 32;

inline int descriptor_distance(const uint8_t* a, const uint8_t* b) {
  int dist = 0;
  for (int i = 0; i < kDescriptorBytes; i += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    dist += __builtin_popcountll(x ^ y);
  }
  return dist;
}

}  // namespace edge_slam
