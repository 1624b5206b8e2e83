// The mobile deployment as one object (stella_vslam's `system`; SlamSystem is the monolithic
// one): everything the mobile nodelet does between receiving bytes and publishing bytes, without
// ROS. It holds the MobileSession (Tracking on the Local-Map, update acceptance; created by
// start() once the camera is known), the KeyFrame sender, the run files and the figures, and
// logs through the core log. The nodelet converts messages, calls one method per callback and
// publishes what it returns.
// Times: `stamp` / `data_now` are data time (the camera's stamps, the bag's clock when one is
// replayed); latencies, resends and throttling use the injected wall clock.
// Thread-safe: the image thread tracks, the sender thread sends, callbacks and timers read.
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "edge_slam/io/run_recorder.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/split/keyframe_sender.h"
#include "edge_slam/split/memory_row.h"
#include "edge_slam/split/mobile_figures.h"
#include "edge_slam/util/rejection_log.h"

namespace edge_slam {

struct MobileSystemSettings {
  OrbParams orb;
  TrackingParams tracking;  // the session keeps the conditions its pacing asks for
  MobileSessionParams session;
  DeliveryParams delivery;
  std::shared_ptr<const BowVocabulary> vocabulary;
  RunFiles files;       // events, metrics, trajectory (as tracked), anchors; keyframes unused
  std::string dataset;  // named in metrics.json
};
// The mobile's sections of config/slam.yaml (orb, tracking, edge_slam, delivery).
MobileSystemSettings load_mobile_system_settings(const ConfigMap& slam);

class MobileSystem {
 public:
  // Creates the run files; throws naming one that cannot be created.
  explicit MobileSystem(MobileSystemSettings settings, WallClock clock = wall_clock_seconds);
  ~MobileSystem();  // writes the outputs a last time

  // Starts tracking with this camera (once; later calls change nothing). Throws when the
  // session cannot be built.
  void start(const PinholeCamera& camera);
  std::shared_ptr<MobileSession> session() const { return std::atomic_load(&session_); }
  const PinholeCamera& camera() const { return camera_; }

  // --- image thread ---
  // A camera frame dropped before tracking: counted per problem, logged once per kind.
  void reject_image(ImageProblem problem, const std::string& why);
  // Tracks a frame (session started) and records it: figures, the CSV row, the outcome of an
  // update that waited on this frame, the pose as tracked and its anchors.
  TrackingResult track(const cv::Mat& rgb, const cv::Mat& depth, double stamp);
  // While lost, a processed frame for the edge every relocalization_frame_period.
  std::optional<FrameRecord> relocalization_frame(double stamp);
  void frame_sent(const FrameRecord& frame, size_t bytes, double stamp);

  // --- sender thread: take_from(session()->outbox()), due(), publish, keyframe_sent() ---
  KeyFrameSender& sender() { return sender_; }
  void keyframe_sent(const KeyFrameRecord& record, size_t bytes);
  double now() const { return clock_(); }

  // --- the edge's messages ---
  void on_ack(const KeyFrameAck& ack);
  // A map update that did not decode: rejected_invalid, logged once per kind.
  void reject_update(const std::string& why);
  UpdateOutcome apply_update(const MapUpdateRecord& update, size_t bytes, double data_now);

  // --- services (need a started session) ---
  std::string set_updates_enabled(bool enabled, double data_now);  // what the controller now says
  std::string reset(double data_now);

  // --- timers ---
  Figures stats() const;  // ~stats: session, traffic and delivery figures
  // Every second and at shutdown: the CSV, trajectory and anchors flushed, metrics.json rewritten;
  // every MemorySampleClock::kPeriodS also a "heap" row (split/memory_row.h) in the CSV.
  void write_outputs();
  uint64_t images_rejected(ImageProblem problem) const { return figures_.images_rejected(problem); }

 private:
  void report_update(uint64_t seq, MapUpdateKind kind, const UpdateOutcome& out, size_t bytes, double latency_ms,
                     double data_now, bool after_deferral);
  EventRow row(const char* event, double data_time) const;
  // The allocator's figures and the map objects alive, at most every MemorySampleClock::kPeriodS
  // (wall): what the process keeps alive, apart from RSS, which also counts kept-free heap and
  // non-heap pages.
  void sample_memory();

  MobileSystemSettings settings_;
  WallClock clock_;
  RunRecorder recorder_;
  KeyFrameSender sender_;
  MobileFigures figures_;
  std::shared_ptr<MobileSession> session_;  // set once by start(), read through session()
  PinholeCamera camera_;                    // image thread (start)
  std::atomic<double> last_frame_stamp_{-1};
  RejectionLog rejected_images_{"dropping a camera frame", "dropping camera frames"};
  RejectionLog malformed_updates_{"rejecting a malformed map update", "rejecting malformed map updates"};
  LogThrottle tracking_warning_{5.0}, update_error_{5.0}, metrics_error_{30.0};
  std::mutex write_mutex_;  // write_outputs: timer and destructor
  MemorySampleClock heap_clock_;  // wall clock; under write_mutex_
};

}  // namespace edge_slam
