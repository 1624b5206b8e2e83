// At most one log line per `period` seconds for a recurring problem (time is an argument, so the
// owner's tests decide what "later" means). The first call is always allowed.
#pragma once
#include <limits>
#include <mutex>

namespace edge_slam {

class LogThrottle {
 public:
  explicit LogThrottle(double period_s = 5.0) : period_(period_s) {}
  bool allow(double now) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (now - last_ < period_) return false;
    last_ = now;
    return true;
  }

 private:
  std::mutex mutex_;
  double period_;
  double last_ = -std::numeric_limits<double>::infinity();
};

}  // namespace edge_slam
