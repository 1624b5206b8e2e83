// The mobile's figures: per-frame tracking times, KeyFrame/Frame/update traffic, update
// latencies and Local-Map rebuild times. Published every second as edge_slam_msgs/Stats and
// written to metrics.json in the same shape as the monolithic runner's (plus the split's own).
#pragma once
#include <edge_slam/io/metrics_json.h>
#include <edge_slam/module/mobile_session.h>
#include <edge_slam_msgs/Stats.h>

#include <array>

#include <mutex>
#include <string>
#include <vector>

#include "image_input.h"

namespace edge_slam_mobile {

class MobileMetrics {
 public:
  void on_frame(double tracking_ms) {
    std::lock_guard<std::mutex> lock(mutex_);
    tracking_ms_.push_back(tracking_ms);
  }
  void on_input_rejected(ImageProblem problem) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++inputs_rejected_;
    ++images_rejected_[static_cast<int>(problem)];
  }
  uint64_t images_rejected(ImageProblem problem) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return images_rejected_[static_cast<int>(problem)];
  }
  void on_keyframe_sent(size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++keyframes_sent_;
    keyframe_bytes_ += bytes;
  }
  void on_frame_sent(size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++frames_sent_;
    frame_bytes_ += bytes;
  }
  void on_update(size_t bytes, double latency_ms, bool accepted, double rebuild_ms) {
    std::lock_guard<std::mutex> lock(mutex_);
    update_bytes_ += bytes;
    update_latency_ms_.push_back(latency_ms);
    if (accepted) rebuild_ms_.push_back(rebuild_ms);
  }
  void on_deferred_update(bool accepted, double rebuild_ms) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (accepted) rebuild_ms_.push_back(rebuild_ms);
  }

  edge_slam_msgs::Stats stats(const edge_slam::MobileSession& s) const {
    edge_slam_msgs::Stats m;
    m.node = "mobile";
    auto add = [&m](const char* name, double v) {
      m.names.push_back(name);
      m.values.push_back(v);
    };
    const edge_slam::TrackingCounters t = s.tracking_counters();
    const edge_slam::MapUpdateCounters u = s.update_counters();
    add("frames", t.frames);
    add("frames_tracked", t.frames_tracked);
    add("times_lost", t.times_lost);
    add("relocalizations", t.relocalizations);
    add("keyframes_created", static_cast<double>(s.keyframes_sent()));
    add("local_map_keyframes", static_cast<double>(s.local_map_keyframes()));
    add("local_map_points", static_cast<double>(s.local_map_points()));
    add("local_map_peak", static_cast<double>(s.local_map_peak()));
    add("time_constraint_s", s.time_constraint());
    add("updates_received", u.received);
    add("updates_accepted", u.accepted);
    add("updates_rejected_controller", u.rejected_controller);
    add("updates_rejected_initializing", u.rejected_initializing);
    add("updates_rejected_redundant", u.rejected_redundant);
    add("updates_rejected_keyframe_rate", u.rejected_keyframe_rate);
    add("updates_rejected_not_lost", u.rejected_not_lost);
    add("updates_rejected_invalid", u.rejected_invalid);
    add("outbox_queued", static_cast<double>(s.outbox_size()));
    std::lock_guard<std::mutex> lock(mutex_);
    add("inputs_rejected", static_cast<double>(inputs_rejected_));
    add("images_rejected_stamp", static_cast<double>(images_rejected_[static_cast<int>(ImageProblem::kStamp)]));
    add("images_rejected_encoding", static_cast<double>(images_rejected_[static_cast<int>(ImageProblem::kEncoding)]));
    add("images_rejected_size", static_cast<double>(images_rejected_[static_cast<int>(ImageProblem::kSize)]));
    add("images_rejected_depth", static_cast<double>(images_rejected_[static_cast<int>(ImageProblem::kDepth)]));
    add("keyframes_sent", static_cast<double>(keyframes_sent_));
    add("keyframe_bytes_sent", static_cast<double>(keyframe_bytes_));
    add("frames_sent", static_cast<double>(frames_sent_));
    add("frame_bytes_sent", static_cast<double>(frame_bytes_));
    add("update_bytes_received", static_cast<double>(update_bytes_));
    add("tracking_ms_last", tracking_ms_.empty() ? 0.0 : tracking_ms_.back());
    add("rebuild_ms_last", rebuild_ms_.empty() ? 0.0 : rebuild_ms_.back());
    add("update_latency_ms_last", update_latency_ms_.empty() ? 0.0 : update_latency_ms_.back());
    return m;
  }

  edge_slam::MetricsJson json(const edge_slam::MobileSession& s, const std::string& dataset) const {
    const edge_slam::TrackingCounters t = s.tracking_counters();
    const edge_slam::MapUpdateCounters u = s.update_counters();
    edge_slam::MetricsJson updates;
    updates.integer("received", u.received)
        .integer("accepted", u.accepted)
        .integer("relocalization_applied", u.relocalization_applied)
        .integer("rejected_controller", u.rejected_controller)
        .integer("rejected_initializing", u.rejected_initializing)
        .integer("rejected_redundant", u.rejected_redundant)
        .integer("rejected_keyframe_rate", u.rejected_keyframe_rate)
        .integer("rejected_not_lost", u.rejected_not_lost)
        .integer("rejected_invalid", u.rejected_invalid);
    const edge_slam::MobileKeyFrameStats k = s.keyframe_stats();
    const edge_slam::MobileUpdateStats us = s.update_stats();
    edge_slam::MetricsJson kf_stats;
    kf_stats.integer("made", static_cast<long long>(k.made))
        .integer("fewer_than_reference", static_cast<long long>(k.fewer_than_reference))
        .integer("needs_close_points", static_cast<long long>(k.needs_close_points))
        .integer("weak_tracking", static_cast<long long>(k.weak_tracking))
        .integer("reference_mobile_made", static_cast<long long>(k.reference_mobile_made))
        .number("mean_inliers", k.made ? double(k.inliers_sum) / k.made : 0.0)
        .number("mean_reference_points", k.made ? double(k.reference_points_sum) / k.made : 0.0);
    edge_slam::MetricsJson update_stats;
    update_stats.integer("installed", static_cast<long long>(us.installed))
        .integer("tracked_points_before", static_cast<long long>(us.tracked_points_before))
        .integer("tracked_points_kept", static_cast<long long>(us.tracked_points_kept))
        .number("min_kept_share", us.min_kept_share)
        .integer("mobile_keyframes_dropped", static_cast<long long>(us.mobile_keyframes_dropped))
        .integer("keyframes_carried", static_cast<long long>(us.keyframes_carried))
        .number("max_correction_m", us.max_correction_m)
        .number("mean_correction_m", us.installed ? us.sum_correction_m / us.installed : 0.0);
    edge_slam::MetricsJson m;
    m.text("mode", "split").text("dataset", dataset);
    m.object("keyframe_stats", kf_stats).object("update_stats", update_stats);
    std::lock_guard<std::mutex> lock(mutex_);
    m.integer("frames", t.frames)
        .integer("frames_tracked", t.frames_tracked)
        .integer("times_lost", t.times_lost)
        .integer("relocalizations", t.relocalizations)
        .integer("rejected_inputs", t.rejected_inputs + static_cast<long long>(inputs_rejected_))
        .integer("keyframes", static_cast<long long>(s.keyframes_sent()))
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
        .timing("rebuild_ms", rebuild_ms_)
        .timing("update_latency_ms", update_latency_ms_)
        .timing("tracking_ms", tracking_ms_);
    return m;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<double> tracking_ms_, rebuild_ms_, update_latency_ms_;
  uint64_t inputs_rejected_ = 0, keyframes_sent_ = 0, frames_sent_ = 0;
  std::array<uint64_t, kImageProblemKinds> images_rejected_{};
  uint64_t keyframe_bytes_ = 0, frame_bytes_ = 0, update_bytes_ = 0;
};

}  // namespace edge_slam_mobile
