// Counts rejected inputs (malformed messages, unusable camera frames) per reason, so a flood of
// bad input is logged once per kind of problem instead of once per message, and the totals can
// be reported. A reason's kind is its text with every run of digits replaced by '#': "keypoint
// index 7 >= 5" and "keypoint index 9 >= 5" are the same problem seen twice. Reasons may quote
// what was received (an image encoding), so at most kMaxKinds are kept; later kinds share one.
#pragma once
#include <cctype>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace edge_slam {

class RejectionCounter {
 public:
  // Counts one rejection; returns how many of this kind there have been (1 = first: log it).
  static constexpr size_t kMaxKinds = 64;
  static constexpr const char* kOtherKinds = "(other kinds)";

  uint64_t add(const std::string& reason) {
    std::string kind = reason_kind(reason);
    std::lock_guard<std::mutex> lock(mutex_);
    ++total_;
    if (by_kind_.size() >= kMaxKinds && !by_kind_.count(kind)) kind = kOtherKinds;
    return ++by_kind_[kind];
  }
  uint64_t total() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return total_;
  }
  std::map<std::string, uint64_t> by_kind() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return by_kind_;
  }

  static std::string reason_kind(const std::string& reason) {
    std::string kind;
    kind.reserve(reason.size());
    for (char c : reason) {
      const bool digit = std::isdigit(static_cast<unsigned char>(c)) != 0;
      if (!digit) kind += c;
      else if (kind.empty() || kind.back() != '#') kind += '#';
    }
    return kind;
  }

 private:
  mutable std::mutex mutex_;
  uint64_t total_ = 0;
  std::map<std::string, uint64_t> by_kind_;  // at most kMaxKinds + 1 entries
};

}  // namespace edge_slam
