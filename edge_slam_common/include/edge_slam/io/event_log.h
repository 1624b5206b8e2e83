// Per-event measurements as CSV, one row per KeyFrame sent/received, update built/applied,
// frame tracked ... with one typed schema (EventLog::header(); scripts/bench/pipeline_stats.py
// reads it by column name). Rows are appended to a memory buffer under a short lock and written
// to the file by flush(), outside the lock, so a slow disk never stalls tracking or mapping.
//
// Columns (-1 or empty: does not apply to the row):
//   wall_time     Unix seconds when the row was made
//   data_time     message / sensor time (simulated when a bag is replayed)
//   event         frame, keyframe_sent, frame_sent, update, controller, reset (mobile);
//                 keyframe, frame, update_sent, loop, merge, merge_restored (a merge of the
//                 map file the edge restored, told again; edge)
//   seq, bytes    the message's seq and serialised size
//   latency_ms    transmit latency (creation or publication on the other side -> received here)
//   duration_ms   processing: tracking, Local-Map rebuild (an installed update), update construction
//   cpu_ms        frame rows: CPU time of the tracking thread for the same work (duration_ms is wall
//                 time and includes waiting for a core, which the edge shares when both run on one PC)
//   inliers       frame rows: the tracked pose's inlier matches (0 when not tracked): with the
//                 keyframe_sent rows' frame_stamp, which weak frame became a KeyFrame
//   map_keyframes KeyFrames in the node's map after the event
//   frame_stamp   data stamp of the last frame the mobile tracked when the event happened: an
//                 installed update lies between this frame and the next (where the online
//                 trajectory may jump)
//   state         frame rows: the tracking state (OK, LOST, ...)
//   kind          update / update_sent rows: periodic or relocalization; update_sent also
//                 divergence (a Local-Map update the edge sent early, edge_slam/update_on_divergence)
//   decision      update rows: the mobile's decision (accepted, controller, ..., deferred, error);
//                 edge keyframe rows: the verdict; edge frame rows: answered, no candidates, refused;
//                 malformed: the message did not decode
//   deferred      update rows: 1 on the second row of an update deferred by eq. (1), its final
//                 outcome (no transfer: bytes 0); 0 otherwise
//   keyframes, points   update_sent rows: what the update carries
//   detail        free text (a controller message, a loop, "reset")
#pragma once
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "edge_slam/util/wall_clock.h"

namespace edge_slam {

struct EventRow {
  double wall_time = 0;  // set by EventLog::add
  double data_time = 0;
  std::string event;
  uint64_t seq = 0;
  size_t bytes = 0;
  double latency_ms = -1;
  double duration_ms = -1;
  double cpu_ms = -1;
  long inliers = -1;
  long map_keyframes = -1;
  double frame_stamp = -1;
  std::string state, kind, decision;
  int deferred = 0;
  long keyframes = -1, points = -1;
  std::string detail;
};

class EventLog {
 public:
  // An empty path disables the log. Throws when the file cannot be created.
  explicit EventLog(const std::string& path = "", WallClock clock = wall_clock_seconds);
  ~EventLog();
  bool enabled() const { return enabled_; }
  // Stamps the row with the clock (wall_time); commas in its text become ';'.
  void add(EventRow row);
  void flush();  // call from one thread at a time (a timer, the destructor)

  static const char* header();

 private:
  bool enabled_ = false;
  WallClock clock_;
  std::ofstream file_;
  std::mutex mutex_;  // guards pending_ only
  std::vector<EventRow> pending_;
};

}  // namespace edge_slam
