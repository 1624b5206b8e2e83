// The core's log: every message the SLAM library prints goes through log(), which hands it to
// one settable sink. The default sink writes the message to stderr (the tools and the runner);
// the nodelets install one that forwards to rosconsole, so the core's lines carry the node's
// name and level like the nodelet's own. Messages keep their "[module]" prefixes.
// Thread-safe: any thread may log while another sets the sink.
#pragma once
#include <functional>
#include <sstream>
#include <string>

namespace edge_slam {

enum class LogLevel { kDebug, kInfo, kWarn, kError };
const char* to_string(LogLevel level);

using LogSink = std::function<void(LogLevel, const std::string& message)>;

// Replaces the sink (an empty function restores the default) and returns the previous one.
LogSink set_log_sink(LogSink sink);
// The default sink prints kInfo and above; kDebug lines are dropped unless this lowers it.
void set_stderr_log_level(LogLevel lowest);

// A trailing newline of `message` is dropped (each message is one line to the sink).
void log(LogLevel level, const std::string& message);
inline void log_debug(const std::string& message) { log(LogLevel::kDebug, message); }
inline void log_info(const std::string& message) { log(LogLevel::kInfo, message); }
inline void log_warn(const std::string& message) { log(LogLevel::kWarn, message); }
inline void log_error(const std::string& message) { log(LogLevel::kError, message); }

// The parts of a message, streamed into one string: log_info(log_text("KF ", id, ": ", n, " matches")).
template <class... Parts>
std::string log_text(const Parts&... parts) {
  std::ostringstream s;
  (s << ... << parts);
  return s.str();
}

}  // namespace edge_slam
