// What a node leaves of a run on disk, each file optional (an empty path: not written):
// - events:     the per-event CSV (io/event_log.h), buffered, written by flush()
// - metrics:    metrics.json (io/metrics_json.h), rewritten atomically on every call
// - trajectory: the poses as tracked (TUM, T_wc of every tracked frame) ...
// - anchors:    ... and the same frames on their reference KeyFrames plus each new KeyFrame on
//               its parent (io/anchors_file.h): with the edge's final KeyFrames they give the
//               final trajectory (tools/compose_trajectory)
// - keyframes:  the edge's KeyFrame poses and culled KeyFrames (io/anchors_file.h), rewritten
//               atomically on every call
// The trajectory and anchors are flushed every kLinesPerFlush lines and by flush(), which a
// node calls every second, so both files are complete while it runs, not only at its end.
// Thread-safe.
#pragma once
#include <Eigen/Geometry>
#include <fstream>
#include <mutex>
#include <string>

#include "edge_slam/io/anchors_file.h"
#include "edge_slam/io/event_log.h"
#include "edge_slam/io/metrics_json.h"

namespace edge_slam {

struct RunFiles {
  std::string events, metrics, trajectory, anchors, keyframes;
};

class RunRecorder {
 public:
  static constexpr int kLinesPerFlush = 30;

  // Creates the folders and the line files (truncated, with their header); throws naming a file
  // that cannot be created.
  explicit RunRecorder(const RunFiles& files, WallClock clock = wall_clock_seconds);
  ~RunRecorder();

  void event(EventRow row);
  void pose(double stamp, const Eigen::Isometry3d& T_wc);
  void anchor(const FrameAnchor& frame);
  void anchor(const KeyFrameLink& keyframe);
  // Both throw std::runtime_error naming the file when it cannot be written.
  void metrics(const MetricsJson& m);
  void keyframes(const EdgeKeyFrames& k);
  void flush();

  bool writes_metrics() const { return !files_.metrics.empty(); }
  bool writes_keyframes() const { return !files_.keyframes.empty(); }

 private:
  // A text file written line by line from one thread and flushed from another.
  struct LineFile {
    std::mutex mutex;
    std::ofstream out;
    int unflushed = 0;
    void open(const std::string& path, const char* header);
    template <class Write>
    void line(Write write);
    void flush();
  };

  RunFiles files_;
  EventLog events_;
  LineFile trajectory_, anchors_;
  std::mutex whole_files_;  // metrics.json and the KeyFrames file: timer and destructor
};

}  // namespace edge_slam
