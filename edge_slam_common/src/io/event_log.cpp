#include "edge_slam/io/event_log.h"

#include <algorithm>
#include <iomanip>
#include <stdexcept>

#include "edge_slam/io/output_path.h"

namespace edge_slam {
namespace {
void no_commas(std::string& s) { std::replace(s.begin(), s.end(), ',', ';'); }  // keep the CSV well-formed
}  // namespace

const char* EventLog::header() {
  return "wall_time,data_time,event,seq,bytes,latency_ms,duration_ms,cpu_ms,inliers,map_keyframes,frame_stamp,state,kind,decision,"
         "deferred,keyframes,points,detail";
}

EventLog::EventLog(const std::string& path, WallClock clock) : clock_(std::move(clock)) {
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
  row.wall_time = clock_();
  for (std::string* s : {&row.event, &row.state, &row.kind, &row.decision, &row.detail}) no_commas(*s);
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.push_back(std::move(row));
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
          << r.bytes << ',' << std::setprecision(3) << r.latency_ms << ',' << r.duration_ms << ',' << r.cpu_ms << ','
          << r.inliers << ',' << r.map_keyframes
          << ',' << std::setprecision(6) << r.frame_stamp << ',' << r.state << ',' << r.kind << ',' << r.decision << ','
          << r.deferred << ',' << r.keyframes << ',' << r.points << ',' << r.detail << '\n';
  file_.flush();
}

}  // namespace edge_slam
