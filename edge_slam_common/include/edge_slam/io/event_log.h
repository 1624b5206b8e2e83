// Per-event measurements as CSV (one row per KeyFrame sent/received, update built/applied,
// frame tracked ...). Rows are appended to a memory buffer under a short lock and written to
// the file by flush(), outside the lock, so a slow disk never stalls tracking or mapping.
#pragma once
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

namespace edge_slam {

struct EventRow {
  double wall_time = 0;     // Unix seconds
  double data_time = 0;     // message/sensor time (simulated when a bag is replayed)
  std::string event;        // e.g. keyframe_sent, update_applied
  uint64_t seq = 0;
  size_t bytes = 0;         // serialized message size
  double latency_ms = -1;   // transmit latency where it applies (-1: none)
  double duration_ms = -1;  // processing time where it applies (-1: none)
  long map_keyframes = -1;  // KeyFrames in the node's map after the event (-1: not recorded)
  std::string detail;       // decision, verdict, kind ... (no commas)
};

class EventLog {
 public:
  // An empty path disables the log. Throws when the file cannot be created.
  explicit EventLog(const std::string& path = "");
  ~EventLog();
  bool enabled() const { return enabled_; }
  void add(EventRow row);
  // The same, stamped with the wall clock now.
  void add(const char* event, double data_time, uint64_t seq, size_t bytes, double latency_ms, double duration_ms,
           long map_keyframes, std::string detail);
  void flush();  // call from one thread at a time (a timer, the destructor)

  static const char* header();

 private:
  bool enabled_ = false;
  std::ofstream file_;
  std::mutex mutex_;  // guards pending_ only
  std::vector<EventRow> pending_;
};

}  // namespace edge_slam
