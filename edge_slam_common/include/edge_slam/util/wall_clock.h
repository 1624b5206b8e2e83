// Wall-clock time in Unix seconds, for latencies measured across processes (a KeyFrame's
// creation on the mobile to its arrival on the edge). Replayed bags run on simulated time, so
// message stamps cannot serve; across machines the clocks must be synchronised (chrony/NTP).
// Classes that stamp or compare times take a WallClock, so their gtests can give them any time.
#pragma once
#include <chrono>
#include <functional>

namespace edge_slam {

inline double wall_clock_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

using WallClock = std::function<double()>;

}  // namespace edge_slam
