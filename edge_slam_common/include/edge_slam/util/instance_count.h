// How many objects of a type are alive, for telling a leak from fragmentation.
//
// The mobile's live heap rose 0.3 MB/min on the 10-minute run while its Local-Map stayed at its
// cap (docs/benchmarks/2026-12-07/mobile_live_heap): either map objects outlive the Local-Map
// (a KeyFrame or point kept by someone after an update replaced it) or containers keep their
// high-water capacity. Counting the map's objects as they are made and destroyed tells which.
// A class holds an InstanceCount<itself> as its last member; the count is one relaxed atomic
// increment per construction, nothing per use.
#pragma once
#include <atomic>
#include <cstdint>

namespace edge_slam {

template <typename T>
class InstanceCount {
 public:
  static int64_t alive() { return count_.load(std::memory_order_relaxed); }

  InstanceCount() { count_.fetch_add(1, std::memory_order_relaxed); }
  InstanceCount(const InstanceCount&) { count_.fetch_add(1, std::memory_order_relaxed); }
  InstanceCount(InstanceCount&&) noexcept { count_.fetch_add(1, std::memory_order_relaxed); }
  InstanceCount& operator=(const InstanceCount&) = default;  // the two objects stay two
  InstanceCount& operator=(InstanceCount&&) noexcept = default;
  ~InstanceCount() { count_.fetch_sub(1, std::memory_order_relaxed); }

 private:
  // One counter per type across the core and the nodelet libraries (an inline variable of a
  // template with default visibility is merged by the dynamic linker).
  inline static std::atomic<int64_t> count_{0};
};

}  // namespace edge_slam
