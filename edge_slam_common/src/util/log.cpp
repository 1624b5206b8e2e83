#include "edge_slam/util/log.h"

#include <atomic>
#include <iostream>
#include <mutex>

namespace edge_slam {
namespace {

std::mutex& sink_mutex() {
  static std::mutex m;
  return m;
}
LogSink& installed_sink() {
  static LogSink sink;
  return sink;
}
std::atomic<int>& stderr_lowest() {
  static std::atomic<int> lowest{static_cast<int>(LogLevel::kInfo)};
  return lowest;
}

void to_stderr(LogLevel level, const std::string& message) {
  if (static_cast<int>(level) < stderr_lowest().load()) return;
  std::cerr << message << '\n';  // one insertion per line: lines of two threads do not mix
}

}  // namespace

const char* to_string(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "debug";
    case LogLevel::kInfo: return "info";
    case LogLevel::kWarn: return "warn";
    case LogLevel::kError: return "error";
  }
  return "?";
}

LogSink set_log_sink(LogSink sink) {
  std::lock_guard<std::mutex> lock(sink_mutex());
  LogSink previous = std::move(installed_sink());
  installed_sink() = std::move(sink);
  return previous;
}

void set_stderr_log_level(LogLevel lowest) { stderr_lowest() = static_cast<int>(lowest); }

void log(LogLevel level, const std::string& text) {
  const std::string message = !text.empty() && text.back() == '\n' ? text.substr(0, text.size() - 1) : text;
  LogSink sink;
  {
    std::lock_guard<std::mutex> lock(sink_mutex());
    sink = installed_sink();  // a copy: the sink runs outside the lock, and may log itself
  }
  if (sink) sink(level, message);
  else to_stderr(level, message);
}

}  // namespace edge_slam
