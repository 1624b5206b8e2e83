// A hash map from 32-bit ids to values in one flat array (open addressing, linear probing,
// backward-shift deletion, load <= 1/2), for the Map's id -> KeyFrame / MapPoint tables: the
// tracker resolves ~10^4 map point ids a frame, and std::unordered_map costs a bucket array
// read plus a node chase (two cache misses) per lookup, where this costs one slot read, which
// batch lookups can prefetch (slot_address). Iteration order is the slot order: callers must
// not depend on it. kNoId cannot be a key (it marks empty slots).
#pragma once
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "edge_slam/util/ids.h"

namespace edge_slam {

template <typename V>
class FlatIdMap {
 public:
  struct Slot {
    uint32_t key = kNoId;
    V value{};
  };

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }

  // Null when absent.
  const V* find(uint32_t key) const {
    if (key == kNoId || slots_.empty()) return nullptr;
    for (size_t i = home(key);; i = (i + 1) & mask_) {
      if (slots_[i].key == key) return &slots_[i].value;
      if (slots_[i].key == kNoId) return nullptr;
    }
  }
  bool contains(uint32_t key) const { return find(key) != nullptr; }

  // Inserts or overwrites. kNoId is ignored.
  void put(uint32_t key, V value) {
    if (key == kNoId) return;
    if (2 * (size_ + 1) > slots_.size()) grow(slots_.empty() ? 16 : 2 * slots_.size());
    for (size_t i = home(key);; i = (i + 1) & mask_) {
      if (slots_[i].key == key) {
        slots_[i].value = std::move(value);
        return;
      }
      if (slots_[i].key == kNoId) {
        slots_[i].key = key;
        slots_[i].value = std::move(value);
        ++size_;
        return;
      }
    }
  }

  // True when the key was present.
  bool erase(uint32_t key) {
    if (key == kNoId || slots_.empty()) return false;
    size_t i = home(key);
    while (slots_[i].key != key) {
      if (slots_[i].key == kNoId) return false;
      i = (i + 1) & mask_;
    }
    // Backward shift: move later members of the probe run into the hole while that keeps
    // each of them reachable from its home slot, so no tombstones are needed.
    for (size_t j = (i + 1) & mask_; slots_[j].key != kNoId; j = (j + 1) & mask_) {
      const size_t h = home(slots_[j].key);
      const bool reachable_from_hole = ((j - h) & mask_) >= ((j - i) & mask_);
      if (reachable_from_hole) {
        slots_[i] = std::move(slots_[j]);
        i = j;
      }
    }
    slots_[i] = Slot{};
    --size_;
    return true;
  }

  void clear() {
    for (Slot& s : slots_) s = Slot{};
    size_ = 0;
  }
  void reserve(size_t n) {
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    if (cap > slots_.size()) grow(cap);
  }
  void swap(FlatIdMap& other) {
    slots_.swap(other.slots_);
    std::swap(mask_, other.mask_);
    std::swap(shift_, other.shift_);
    std::swap(size_, other.size_);
  }

  // Where `key` would be looked up first: for a prefetch hint ahead of a batch of finds.
  const void* slot_address(uint32_t key) const { return slots_.empty() ? nullptr : &slots_[home(key)]; }

  // Visits every (key, value), in slot order.
  template <typename F>
  void for_each(F&& f) const {
    for (const Slot& s : slots_)
      if (s.key != kNoId) f(s.key, s.value);
  }

 private:
  // Fibonacci hashing: consecutive ids spread over the table.
  size_t home(uint32_t key) const { return static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_) & mask_; }
  void grow(size_t capacity) {
    std::vector<Slot> old;
    old.swap(slots_);
    slots_.resize(capacity);
    mask_ = capacity - 1;
    shift_ = 64;
    for (size_t c = capacity; c > 1; c >>= 1) --shift_;
    size_ = 0;
    for (Slot& s : old)
      if (s.key != kNoId) put(s.key, std::move(s.value));
  }
  std::vector<Slot> slots_;
  size_t mask_ = 0;
  int shift_ = 64;
  size_t size_ = 0;
};

}  // namespace edge_slam
