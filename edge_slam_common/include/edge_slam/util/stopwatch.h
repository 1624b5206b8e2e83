// Milliseconds elapsed on the steady clock since construction: how long a module's step took,
// for the per-step figures in metrics.json (local BA, loop correction, full BA).
#pragma once
#include <chrono>

namespace edge_slam {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace edge_slam
