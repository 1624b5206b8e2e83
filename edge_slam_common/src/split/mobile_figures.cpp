#include "edge_slam/split/mobile_figures.h"

#include <algorithm>

#include "edge_slam/module/mobile_session.h"

namespace edge_slam {

void MobileFigures::on_frame(double tracking_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  tracking_ms_.add(tracking_ms);
}
void MobileFigures::on_input_rejected(ImageProblem problem) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++inputs_rejected_;
  ++images_rejected_[static_cast<int>(problem)];
}
uint64_t MobileFigures::images_rejected(ImageProblem problem) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return images_rejected_[static_cast<int>(problem)];
}
void MobileFigures::on_keyframe_sent(size_t bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++keyframes_sent_;
  keyframe_bytes_ += bytes;
}
void MobileFigures::on_frame_sent(size_t bytes) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++frames_sent_;
  frame_bytes_ += bytes;
}
void MobileFigures::on_update(size_t bytes, double latency_ms, bool accepted, double rebuild_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  update_bytes_ += bytes;
  update_latency_ms_.add(latency_ms);
  if (accepted) rebuild_ms_.add(rebuild_ms);
}
void MobileFigures::on_deferred_update(bool accepted, double rebuild_ms) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (accepted) rebuild_ms_.add(rebuild_ms);
}

void MobileFigures::on_heap(const HeapUsage& h) {
  std::lock_guard<std::mutex> lock(mutex_);
  heap_last_ = h;
  heap_in_use_peak_ = std::max(heap_in_use_peak_, h.in_use_bytes);
  ++heap_samples_;
}

Figures MobileFigures::stats(const MobileSession& s) const {
  Figures f;
  const TrackingCounters t = s.tracking_counters();
  const MapUpdateCounters u = s.update_counters();
  f.add("frames", t.frames)
      .add("frames_tracked", t.frames_tracked)
      .add("times_lost", t.times_lost)
      .add("relocalizations", t.relocalizations)
      .add("keyframes_created", static_cast<double>(s.keyframes_sent()))
      .add("local_map_keyframes", static_cast<double>(s.local_map_keyframes()))
      .add("local_map_points", static_cast<double>(s.local_map_points()))
      .add("local_map_peak", static_cast<double>(s.local_map_peak()))
      .add("time_constraint_s", s.time_constraint())
      .add("updates_received", u.received)
      .add("updates_accepted", u.accepted)
      .add("updates_rejected_controller", u.rejected_controller)
      .add("updates_rejected_initializing", u.rejected_initializing)
      .add("updates_rejected_redundant", u.rejected_redundant)
      .add("updates_rejected_keyframe_rate", u.rejected_keyframe_rate)
      .add("updates_rejected_not_lost", u.rejected_not_lost)
      .add("updates_rejected_invalid", u.rejected_invalid)
      .add("outbox_queued", static_cast<double>(s.outbox_size()));
  std::lock_guard<std::mutex> lock(mutex_);
  auto rejected = [this](ImageProblem p) { return static_cast<double>(images_rejected_[static_cast<int>(p)]); };
  f.add("inputs_rejected", static_cast<double>(inputs_rejected_))
      .add("images_rejected_stamp", rejected(ImageProblem::kStamp))
      .add("images_rejected_encoding", rejected(ImageProblem::kEncoding))
      .add("images_rejected_size", rejected(ImageProblem::kSize))
      .add("images_rejected_depth", rejected(ImageProblem::kDepth))
      .add("keyframes_sent", static_cast<double>(keyframes_sent_))
      .add("keyframe_bytes_sent", static_cast<double>(keyframe_bytes_))
      .add("frames_sent", static_cast<double>(frames_sent_))
      .add("frame_bytes_sent", static_cast<double>(frame_bytes_))
      .add("update_bytes_received", static_cast<double>(update_bytes_))
      .add("tracking_ms_last", tracking_ms_.last())
      .add("rebuild_ms_last", rebuild_ms_.last())
      .add("update_latency_ms_last", update_latency_ms_.last())
      .add("heap_in_use_mb", heap_last_.in_use_bytes / 1e6);
  return f;
}

MetricsJson MobileFigures::json(const MobileSession& s, const std::string& dataset) const {
  const TrackingCounters t = s.tracking_counters();
  const MapUpdateCounters u = s.update_counters();
  MetricsJson updates;
  updates.integer("received", u.received)
      .integer("accepted", u.accepted)
      .integer("relocalization_applied", u.relocalization_applied)
      .integer("rejected_controller", u.rejected_controller)
      .integer("rejected_initializing", u.rejected_initializing)
      .integer("rejected_redundant", u.rejected_redundant)
      .integer("rejected_keyframe_rate", u.rejected_keyframe_rate)
      .integer("rejected_not_lost", u.rejected_not_lost)
      .integer("rejected_invalid", u.rejected_invalid);
  const MobileKeyFrameStats k = s.keyframe_stats();
  const MobileUpdateStats us = s.update_stats();
  MetricsJson kf_stats;
  kf_stats.integer("made", static_cast<long long>(k.made))
      .integer("fewer_than_reference", static_cast<long long>(k.fewer_than_reference))
      .integer("needs_close_points", static_cast<long long>(k.needs_close_points))
      .integer("weak_tracking", static_cast<long long>(k.weak_tracking))
      .integer("reference_mobile_made", static_cast<long long>(k.reference_mobile_made))
      .integer("points_refuted", static_cast<long long>(k.points_refuted))
      .number("mean_inliers", k.made ? double(k.inliers_sum) / k.made : 0.0)
      .number("mean_reference_points", k.made ? double(k.reference_points_sum) / k.made : 0.0);
  MetricsJson update_stats;
  update_stats.integer("installed", static_cast<long long>(us.installed))
      .integer("tracked_points_before", static_cast<long long>(us.tracked_points_before))
      .integer("tracked_points_kept", static_cast<long long>(us.tracked_points_kept))
      .integer("tracked_points_followed", static_cast<long long>(us.tracked_points_followed))
      .number("min_kept_share", us.min_kept_share)
      .integer("mobile_keyframes_dropped", static_cast<long long>(us.mobile_keyframes_dropped))
      .integer("keyframes_carried", static_cast<long long>(us.keyframes_carried))
      .number("max_correction_m", us.max_correction_m)
      .number("mean_correction_m", us.installed ? us.sum_correction_m / us.installed : 0.0)
      .number("max_reference_rotation_deg", us.max_reference_rotation_deg)
      .number("max_tracked_point_shift_m", us.max_tracked_point_shift_m)
      .integer("heap_releases", static_cast<long long>(us.heap_releases))
      .integer("heap_releases_freeing", static_cast<long long>(us.heap_releases_freeing))
      .number("heap_release_ms", us.heap_release_ms)
      .number("max_heap_release_ms", us.max_heap_release_ms);
  MetricsJson m;
  m.text("mode", "split").text("dataset", dataset);
  m.object("keyframe_stats", kf_stats).object("update_stats", update_stats);
  std::lock_guard<std::mutex> lock(mutex_);
  m.integer("frames", t.frames)
      .integer("frames_tracked", t.frames_tracked)
      .integer("times_lost", t.times_lost)
      .integer("relocalizations", t.relocalizations)
      .integer("rejected_inputs", t.rejected_inputs + static_cast<long long>(inputs_rejected_))
      .integer("keyframes", static_cast<long long>(s.keyframes_sent()))
      .integer("keyframes_created", t.keyframes_created)  // by tracking, as the monolithic runner reports it
      .integer("local_map_keyframes", static_cast<long long>(s.local_map_keyframes()))
      .integer("local_map_peak", static_cast<long long>(s.local_map_peak()))
      .integer("local_map_cap", static_cast<long long>(s.local_map_cap()))
      .integer("keyframes_dropped_by_cap", static_cast<long long>(s.keyframes_dropped_by_cap()))
      .object("updates", updates)
      .integer("keyframes_sent", static_cast<long long>(keyframes_sent_))
      .integer("keyframe_bytes_sent", static_cast<long long>(keyframe_bytes_))
      .integer("frames_sent", static_cast<long long>(frames_sent_))
      .integer("frame_bytes_sent", static_cast<long long>(frame_bytes_))
      .integer("update_bytes_received", static_cast<long long>(update_bytes_))
      .timing_summary("rebuild_ms", rebuild_ms_.stats())
      .timing_summary("update_latency_ms", update_latency_ms_.stats())
      .timing_summary("tracking_ms", tracking_ms_.stats());
  MetricsJson heap;  // the latest reading and the peak of the periodic ones (MB = 10^6 bytes)
  heap.integer("samples", static_cast<long long>(heap_samples_))
      .number("in_use_mb", heap_last_.in_use_bytes / 1e6)
      .number("in_use_peak_mb", heap_in_use_peak_ / 1e6)
      .number("kept_free_mb", heap_last_.kept_free_bytes / 1e6)
      .number("arena_mb", heap_last_.arena_bytes / 1e6)
      .number("mapped_mb", heap_last_.mapped_bytes / 1e6);
  m.object("heap", heap);
  return m;
}

Figures delivery_figures(uint64_t created, const DeliveryCounters& d, double seconds_since_ack) {
  Figures f;
  f.add("delivery_created", static_cast<double>(created))
      .add("delivery_sent", static_cast<double>(d.sent))
      .add("delivery_resent", static_cast<double>(d.resent))
      .add("delivery_acknowledged", static_cast<double>(d.acknowledged))
      .add("delivery_durable", static_cast<double>(d.durable))
      .add("delivery_dropped_by_bound", static_cast<double>(d.dropped_by_bound))
      .add("delivery_queued", static_cast<double>(d.queued))
      .add("delivery_edge_restarts", static_cast<double>(d.edge_restarts))
      .add("link_seconds_since_ack", seconds_since_ack);
  return f;
}

}  // namespace edge_slam
