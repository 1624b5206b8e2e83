#include "edge_slam/io/run_recorder.h"

#include <stdexcept>

#include "edge_slam/io/output_path.h"
#include "edge_slam/io/trajectory_io.h"

namespace edge_slam {

void RunRecorder::LineFile::open(const std::string& path, const char* header) {
  if (path.empty()) return;
  ensure_parent_directory(path);
  out.open(path, std::ios::out | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot create the file '" + path + "'");
  out << header;
  out.flush();
}

template <class Write>
void RunRecorder::LineFile::line(Write write) {
  std::lock_guard<std::mutex> lock(mutex);
  if (!out.is_open()) return;
  write(out);
  if (++unflushed >= kLinesPerFlush) {
    out.flush();
    unflushed = 0;
  }
}

void RunRecorder::LineFile::flush() {
  std::lock_guard<std::mutex> lock(mutex);
  if (!out.is_open()) return;
  out.flush();
  unflushed = 0;
}

RunRecorder::RunRecorder(const RunFiles& files, WallClock clock) : files_(files), events_(files.events, std::move(clock)) {
  trajectory_.open(files.trajectory, "# timestamp tx ty tz qx qy qz qw (T_wc of each tracked frame, as tracked on the mobile)\n");
  anchors_.open(files.anchors, anchors_file_header());
}

RunRecorder::~RunRecorder() { flush(); }

void RunRecorder::event(EventRow row) { events_.add(std::move(row)); }

void RunRecorder::pose(double stamp, const Eigen::Isometry3d& T_wc) {
  trajectory_.line([&](std::ostream& out) { write_tum_pose(out, stamp, T_wc); });
}

void RunRecorder::anchor(const FrameAnchor& frame) {
  anchors_.line([&](std::ostream& out) { write_anchor(out, frame); });
}

void RunRecorder::anchor(const KeyFrameLink& keyframe) {
  anchors_.line([&](std::ostream& out) { write_anchor(out, keyframe); });
}

void RunRecorder::metrics(const MetricsJson& m) {
  if (files_.metrics.empty()) return;
  std::lock_guard<std::mutex> lock(whole_files_);
  m.write(files_.metrics);
}

void RunRecorder::keyframes(const EdgeKeyFrames& k) {
  if (files_.keyframes.empty()) return;
  std::lock_guard<std::mutex> lock(whole_files_);
  write_file_atomically(files_.keyframes, edge_keyframes_text(k));
}

void RunRecorder::flush() {
  events_.flush();
  trajectory_.flush();
  anchors_.flush();
}

}  // namespace edge_slam
