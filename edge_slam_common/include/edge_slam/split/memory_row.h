// One reading of a node's memory for the long run: the allocator's own figures (util/heap_usage.h)
// and the map objects alive in the process (util/instance_count.h) next to what the node's map
// holds, written as the detail of a "heap" row of its CSV (key=value pairs, read by
// scripts/bench/bench_data.py). Alive beyond what the map holds, growing, is a leak of map
// objects; a growing heap with the same counts is not.
#pragma once
#include <cstddef>
#include <string>

#include "edge_slam/util/heap_usage.h"

namespace edge_slam {

// `map_name` prefixes the map's counts: "local_map" (mobile) or "global_map" (edge).
std::string memory_row_detail(const HeapUsage& heap, const char* map_name, size_t map_keyframes, size_t map_points);

// When the next reading is due: every period seconds of the caller's clock.
class MemorySampleClock {
 public:
  static constexpr double kPeriodS = 10.0;
  // True (and the next one scheduled) when a reading is due at `now`.
  bool due(double now) {
    if (now < next_) return false;
    next_ = now + kPeriodS;
    return true;
  }

 private:
  double next_ = 0;
};

}  // namespace edge_slam
