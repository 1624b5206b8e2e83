#include "edge_slam/split/mobile_system.h"

#include <cstdio>

#include "edge_slam/io/config_file.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/split/memory_row.h"
#include "edge_slam/util/heap_usage.h"
#include "edge_slam/util/log.h"

namespace edge_slam {

MobileSystemSettings load_mobile_system_settings(const ConfigMap& slam) {
  MobileSystemSettings s;
  s.orb = load_orb_params(slam);
  s.tracking = load_tracking_params(slam);
  s.session = load_mobile_session_params(slam);
  s.delivery = load_delivery_params(slam);
  return s;
}

MobileSystem::MobileSystem(MobileSystemSettings settings, WallClock clock)
    : settings_(std::move(settings)),
      clock_(std::move(clock)),
      recorder_(settings_.files, clock_),
      sender_(settings_.delivery) {}

MobileSystem::~MobileSystem() { write_outputs(); }

void MobileSystem::start(const PinholeCamera& camera) {
  if (session()) return;
  auto s = std::make_shared<MobileSession>(camera, settings_.orb, settings_.tracking, settings_.vocabulary,
                                           settings_.session, RgbEncoding::kRgb, clock_);
  camera_ = camera;
  std::atomic_store(&session_, s);
}

EventRow MobileSystem::row(const char* event, double data_time) const {
  EventRow r;
  r.event = event;
  r.data_time = data_time;
  r.frame_stamp = last_frame_stamp_;
  if (const auto s = session()) r.map_keyframes = static_cast<long>(s->local_map_keyframes());
  return r;
}

void MobileSystem::reject_image(ImageProblem problem, const std::string& why) {
  figures_.on_input_rejected(problem);
  rejected_images_.reject(why, clock_());
}

TrackingResult MobileSystem::track(const cv::Mat& rgb, const cv::Mat& depth, double stamp) {
  const auto s = session();
  const TrackingResult r = s->track(rgb, depth, stamp);
  last_frame_stamp_ = stamp;
  if (!r.message.empty() && r.state != TrackingState::kOk && tracking_warning_.allow(clock_()))
    log_warn("tracking: " + r.message);
  figures_.on_frame(r.time_ms);
  EventRow e = row("frame", stamp);
  e.seq = r.frame_id;
  e.duration_ms = r.time_ms;
  e.cpu_ms = r.cpu_ms;
  e.inliers = r.inliers;
  e.state = to_string(r.state);
  e.detail = describe(r.diag) + (r.new_keyframe ? " keyframe=1" : " keyframe=0");
  recorder_.event(std::move(e));
  if (auto deferred = s->take_deferred_outcome())
    report_update(deferred->first, MapUpdateKind::kPeriodic, deferred->second, 0, -1, stamp, true);
  if (r.pose_valid) recorder_.pose(stamp, r.T_cw.inverse());
  if (r.pose_valid && r.keyframe_link) recorder_.anchor(*r.keyframe_link);
  if (r.pose_valid && r.frame_anchor) recorder_.anchor(*r.frame_anchor);
  return r;
}

std::optional<FrameRecord> MobileSystem::relocalization_frame(double stamp) {
  const auto s = session();
  return s ? s->take_relocalization_frame(stamp) : std::nullopt;
}

void MobileSystem::frame_sent(const FrameRecord& frame, size_t bytes, double stamp) {
  figures_.on_frame_sent(bytes);
  EventRow e = row("frame_sent", stamp);
  e.seq = frame.seq;
  e.bytes = bytes;
  recorder_.event(std::move(e));
}

void MobileSystem::keyframe_sent(const KeyFrameRecord& record, size_t bytes) {
  figures_.on_keyframe_sent(bytes);
  EventRow e = row("keyframe_sent", record.stamp);
  e.seq = record.seq;
  e.bytes = bytes;
  e.map_keyframes = -1;  // the sender thread does not read the Local-Map
  if (record.reset) e.detail = "reset";
  recorder_.event(std::move(e));
}

void MobileSystem::on_ack(const KeyFrameAck& ack) {
  if (const auto s = session()) s->on_edge_progress(ack.mapped_seq, ack.mapper_busy_elsewhere);
  if (sender_.on_ack(ack, clock_()))
    log_warn("the edge restarted (durable up to KeyFrame seq " + std::to_string(ack.durable_seq) +
             "): resending what came after");
}

void MobileSystem::reject_update(const std::string& why) {
  if (const auto s = session()) s->count_invalid_update();
  malformed_updates_.reject(why, clock_());
}

UpdateOutcome MobileSystem::apply_update(const MapUpdateRecord& update, size_t bytes, double data_now) {
  const auto s = session();
  // Published (edge wall clock) -> received and deserialised here.
  const double latency_ms = (clock_() - update.publish_stamp) * 1e3;
  const UpdateOutcome out = s->apply_update(update, data_now);
  report_update(update.seq, update.kind, out, bytes, latency_ms, data_now, false);
  return out;
}

// One "update" row per update received (bytes > 0) and one more for the final outcome of a
// deferred one (bytes 0, deferred = 1); the figures count the rebuild of every installed update.
void MobileSystem::report_update(uint64_t seq, MapUpdateKind kind, const UpdateOutcome& out, size_t bytes,
                                 double latency_ms, double data_now, bool after_deferral) {
  const bool accepted = out.decision == UpdateDecision::kAccept && out.error.empty();
  if (after_deferral) figures_.on_deferred_update(accepted, out.rebuild_ms);
  else figures_.on_update(bytes, latency_ms, accepted, out.rebuild_ms);
  const std::string kind_text = kind == MapUpdateKind::kRelocalization ? "relocalization" : "periodic";
  EventRow e = row("update", data_now);
  e.seq = seq;
  e.bytes = bytes;
  e.latency_ms = latency_ms;
  e.duration_ms = accepted ? out.rebuild_ms : -1;
  e.kind = kind_text;
  e.decision = out.error.empty() ? to_string(out.decision) : "error";
  e.deferred = after_deferral ? 1 : 0;
  recorder_.event(std::move(e));
  const std::string which = after_deferral ? "deferred" : kind_text;
  if (!out.error.empty()) {
    if (update_error_.allow(clock_()))
      log_error("map update " + std::to_string(seq) + " could not be applied: " + out.error);
  } else if (accepted) {
    char line[200];
    if (after_deferral)
      std::snprintf(line, sizeof line, "applied deferred map update %lu: %zu KeyFrames, %zu points, rebuilt in %.1f ms",
                    static_cast<unsigned long>(seq), out.keyframes, out.map_points, out.rebuild_ms);
    else
      std::snprintf(line, sizeof line,
                    "applied %s map update %lu: %zu KeyFrames, %zu points, staged in %.1f ms, swapped in %.2f ms "
                    "(tracking paused)",
                    which.c_str(), static_cast<unsigned long>(seq), out.keyframes, out.map_points, out.stage_ms,
                    out.rebuild_ms);
    log_info(line);
  } else if (!after_deferral) {
    log_debug("map update " + std::to_string(seq) + " rejected: " + to_string(out.decision));
  }
}

std::string MobileSystem::set_updates_enabled(bool enabled, double data_now) {
  const auto s = session();
  s->set_updates_enabled(enabled);
  const std::string message = s->updates_enabled() ? "map updates enabled" : "map updates disabled";
  log_info("map-update controller: " + message);
  EventRow e = row("controller", data_now);
  e.map_keyframes = -1;
  e.detail = message;
  recorder_.event(std::move(e));
  return message;
}

void MobileSystem::sample_memory() {
  {
    std::lock_guard<std::mutex> lock(write_mutex_);
    if (!heap_clock_.due(clock_())) return;
  }
  const HeapUsage h = read_heap_usage();
  if (!h.supported) return;
  figures_.on_heap(h);
  EventRow e = row("heap", last_frame_stamp_);
  e.bytes = h.in_use_bytes;
  const auto s = session();
  e.detail = memory_row_detail(h, "local_map", s ? s->local_map_keyframes() : 0, s ? s->local_map_points() : 0);
  recorder_.event(std::move(e));
}

std::string MobileSystem::reset(double data_now) {
  const auto s = session();
  const bool sent = s->reset();
  const std::string message = sent ? "reset: newest KeyFrame re-sent with its reset flag; Local-Map cleared"
                                   : "reset: no KeyFrame yet; Local-Map cleared";
  log_warn(message);
  recorder_.event(row("reset", data_now));
  return message;
}

Figures MobileSystem::stats() const {
  const auto s = session();
  if (!s) return {};
  Figures f = figures_.stats(*s);
  f.add(delivery_figures(s->keyframes_sent(), sender_.counters(), sender_.seconds_since_ack(clock_())));
  return f;
}

void MobileSystem::write_outputs() {
  sample_memory();
  recorder_.flush();
  const auto s = session();
  if (!s || !recorder_.writes_metrics()) return;
  std::lock_guard<std::mutex> lock(write_mutex_);
  try {
    MetricsJson m = figures_.json(*s, settings_.dataset);
    m.object("malformed_updates", counts_by_kind(malformed_updates_.counter()))
        .object("camera_frames_dropped", counts_by_kind(rejected_images_.counter()));
    recorder_.metrics(m);
  } catch (const std::exception& e) {
    if (metrics_error_.allow(clock_())) log_error(e.what());
  }
}

}  // namespace edge_slam
