// The mobile's figures: per-frame tracking times, KeyFrame/Frame/update traffic, update
// latencies, Local-Map rebuild times, the camera frames dropped per problem and the heap. Published every
// second (stats(): edge_slam_msgs/Stats) and written to metrics.json (json()) in the same shape
// as the monolithic runner's, plus the split's own. Thread-safe.
#pragma once
#include <array>
#include <mutex>
#include <string>
#include <vector>

#include "edge_slam/io/metrics_json.h"
#include "edge_slam/module/keyframe_delivery.h"
#include "edge_slam/split/image_problem.h"
#include "edge_slam/util/figures.h"
#include "edge_slam/util/heap_usage.h"
#include "edge_slam/util/timing_histogram.h"

namespace edge_slam {

class MobileSession;

class MobileFigures {
 public:
  void on_frame(double tracking_ms);
  void on_input_rejected(ImageProblem problem);
  uint64_t images_rejected(ImageProblem problem) const;
  void on_keyframe_sent(size_t bytes);
  void on_frame_sent(size_t bytes);
  void on_update(size_t bytes, double latency_ms, bool accepted, double rebuild_ms);
  void on_deferred_update(bool accepted, double rebuild_ms);
  void on_heap(const HeapUsage& h);  // a periodic reading (MobileSystem::sample_memory)

  Figures stats(const MobileSession& s) const;
  MetricsJson json(const MobileSession& s, const std::string& dataset) const;

 private:
  mutable std::mutex mutex_;
  // Summarised as they come (util/timing_histogram.h): the mobile's memory does not grow per frame.
  TimingHistogram tracking_ms_, rebuild_ms_, update_latency_ms_;
  uint64_t inputs_rejected_ = 0, keyframes_sent_ = 0, frames_sent_ = 0;
  std::array<uint64_t, kImageProblemKinds> images_rejected_{};
  uint64_t keyframe_bytes_ = 0, frame_bytes_ = 0, update_bytes_ = 0;
  HeapUsage heap_last_;
  size_t heap_in_use_peak_ = 0;
  uint64_t heap_samples_ = 0;
};

// The sender's figures on ~stats: delivery_* counters and link_seconds_since_ack.
Figures delivery_figures(uint64_t created, const DeliveryCounters& d, double seconds_since_ack);

}  // namespace edge_slam
