// A set of 32-bit ids in one flat array (open addressing, linear probing), for the per-frame
// "seen it already?" tests over 10^4 map point ids where std::unordered_set allocates a node
// per insert and chases a pointer per lookup. kNoId cannot be stored (it marks empty slots).
// clear() keeps the capacity, so a set reused frame after frame stops allocating.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "edge_slam/util/ids.h"

namespace edge_slam {

class FlatIdSet {
 public:
  // Room for `n` ids at load <= 1/2 without growing.
  void reserve(size_t n) {
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    if (cap > slots_.size()) rehash(cap);
  }
  // True when `id` was not in the set (and is now). kNoId is never inserted: false.
  bool insert(uint32_t id) {
    if (id == kNoId) return false;
    if (2 * (size_ + 1) > slots_.size()) rehash(slots_.empty() ? 16 : 2 * slots_.size());
    for (size_t i = slot_of(id);; i = (i + 1) & mask_) {
      if (slots_[i] == id) return false;
      if (slots_[i] == kNoId) {
        slots_[i] = id;
        ++size_;
        return true;
      }
    }
  }
  bool contains(uint32_t id) const {
    if (id == kNoId || slots_.empty()) return false;
    for (size_t i = slot_of(id);; i = (i + 1) & mask_) {
      if (slots_[i] == id) return true;
      if (slots_[i] == kNoId) return false;
    }
  }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void clear() {
    std::fill(slots_.begin(), slots_.end(), kNoId);
    size_ = 0;
  }

 private:
  // Fibonacci hashing: consecutive ids (the usual case) spread over the table.
  size_t slot_of(uint32_t id) const { return static_cast<size_t>((id * 0x9E3779B97F4A7C15ull) >> shift_) & mask_; }
  void rehash(size_t capacity) {
    std::vector<uint32_t> old;
    old.swap(slots_);
    slots_.assign(capacity, kNoId);
    mask_ = capacity - 1;
    shift_ = 64;
    for (size_t c = capacity; c > 1; c >>= 1) --shift_;
    size_ = 0;
    for (uint32_t id : old)
      if (id != kNoId) insert(id);
  }
  std::vector<uint32_t> slots_;
  size_t mask_ = 0;
  int shift_ = 64;
  size_t size_ = 0;
};

}  // namespace edge_slam
