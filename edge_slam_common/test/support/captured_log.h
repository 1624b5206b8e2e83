// Test helper: collects what the core logs (util/log.h) while it lives, then puts the previous
// sink back.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "edge_slam/util/log.h"

namespace edge_slam {
namespace test_support {

struct CapturedLog {
  std::vector<std::pair<LogLevel, std::string>> lines;
  LogSink previous;
  CapturedLog() {
    previous = set_log_sink([this](LogLevel level, const std::string& m) { lines.emplace_back(level, m); });
  }
  ~CapturedLog() { set_log_sink(previous); }
};

}  // namespace test_support
}  // namespace edge_slam
