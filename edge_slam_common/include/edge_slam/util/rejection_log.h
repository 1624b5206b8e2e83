// Rejected inputs of one kind (malformed messages on a topic, unusable camera frames): counted
// per reason (util/rejection_counter.h) and reported through the core log, the first of each
// kind of problem at once, then at most one line every `throttle_s` seconds with the totals, so a
// flood of bad input says what is wrong without flooding the log. Time is an argument.
// Thread-safe.
#pragma once
#include <string>

#include "edge_slam/util/log_throttle.h"
#include "edge_slam/util/rejection_counter.h"

namespace edge_slam {

class RejectionLog {
 public:
  // e.g. ("rejecting a malformed map update", "rejecting malformed map updates")
  RejectionLog(std::string one, std::string many, double throttle_s = 5.0);

  // Counts and reports one rejection; returns how many of its kind there have been.
  uint64_t reject(const std::string& why, double now);

  const RejectionCounter& counter() const { return counter_; }
  uint64_t total() const { return counter_.total(); }

 private:
  std::string one_, many_;
  RejectionCounter counter_;
  LogThrottle throttle_;
};

}  // namespace edge_slam
