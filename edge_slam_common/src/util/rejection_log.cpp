#include "edge_slam/util/rejection_log.h"

#include "edge_slam/util/log.h"

namespace edge_slam {

RejectionLog::RejectionLog(std::string one, std::string many, double throttle_s)
    : one_(std::move(one)), many_(std::move(many)), throttle_(throttle_s) {}

uint64_t RejectionLog::reject(const std::string& why, double now) {
  const uint64_t same_kind = counter_.add(why);
  if (same_kind == 1) {
    log_error(one_ + " (first of its kind): " + why);
  } else if (throttle_.allow(now)) {
    log_error(many_ + " (" + std::to_string(counter_.total()) + " so far, " + std::to_string(same_kind) +
              " like this): " + why);
  }
  return same_kind;
}

}  // namespace edge_slam
