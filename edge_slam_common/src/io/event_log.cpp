#include "edge_slam/io/event_log.h"

#include "edge_slam/io/output_path.h"
#include "edge_slam/util/wall_clock.h"

#include <algorithm>
#include <iomanip>
#include <stdexcept>

namespace edge_slam {

const char* EventLog::header() {
  return "wall_time,data_time,event,seq,bytes,latency_ms,duration_ms,map_keyframes,detail";
}

EventLog::EventLog(const std::string& path) {
  if (path.empty()) return;
  ensure_parent_directory(path);
  file_.open(path, std::ios::out | std::ios::trunc);
  if (!file_) throw std::runtime_error("cannot create the statistics file '" + path + "'");
  file_ << header() << '\n';
  file_.flush();
  enabled_ = true;
}

EventLog::~EventLog() { flush(); }

void EventLog::add(EventRow row) {
  if (!enabled_) return;
  std::replace(row.detail.begin(), row.detail.end(), ',', ';');  // keep the CSV well-formed
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.push_back(std::move(row));
}

void EventLog::add(const char* event, double data_time, uint64_t seq, size_t bytes, double latency_ms,
                   double duration_ms, long map_keyframes, std::string detail) {
  EventRow row;
  row.wall_time = wall_clock_seconds();
  row.data_time = data_time;
  row.event = event;
  row.seq = seq;
  row.bytes = bytes;
  row.latency_ms = latency_ms;
  row.duration_ms = duration_ms;
  row.map_keyframes = map_keyframes;
  row.detail = std::move(detail);
  add(std::move(row));
}

void EventLog::flush() {
  if (!enabled_) return;
  std::vector<EventRow> rows;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    rows.swap(pending_);
  }
  file_ << std::fixed;
  for (const EventRow& r : rows)
    file_ << std::setprecision(6) << r.wall_time << ',' << r.data_time << ',' << r.event << ',' << r.seq << ','
          << r.bytes << ',' << std::setprecision(3) << r.latency_ms << ',' << r.duration_ms << ','
          << r.map_keyframes << ',' << r.detail << '\n';
  file_.flush();
}

}  // namespace edge_slam
