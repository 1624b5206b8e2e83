// The edge deployment as one object (the counterpart of split/mobile_system.h): everything the
// edge nodelet does between receiving bytes and publishing bytes, without ROS. It holds the
// EdgeSession (Global-Map, Local-Mapping, Loop-Closing, conditions 1-2, the update modules),
// its durability (split/edge_durability.h), the run files and the figures, and logs through
// the core log. Wall-clock times come from the injected clock; `data_now` is data time.
// Thread-safe: message callbacks, timers and services run on several threads.
#pragma once
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "edge_slam/feature/orb_params.h"
#include "edge_slam/io/run_recorder.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/split/edge_durability.h"
#include "edge_slam/split/memory_row.h"
#include "edge_slam/util/figures.h"
#include "edge_slam/util/log_throttle.h"
#include "edge_slam/util/rejection_log.h"

namespace edge_slam {

struct EdgeSystemSettings {
  PinholeCamera camera;
  OrbParams orb;  // the pyramid the mobile's features were made with
  EdgeSessionParams session;
  DurabilityParams durability;  // checkpoint_period from the config, the file from the deployment
  bool restore_on_start = true;
  std::shared_ptr<const BowVocabulary> vocabulary;
  RunFiles files;  // events, metrics, keyframes
};
// The edge's sections of config/slam.yaml (orb, tracking's conditions 1-2, edge_slam, delivery).
EdgeSystemSettings load_edge_system_settings(const ConfigMap& slam);

class EdgeSystem {
 public:
  enum class Topic { kKeyFrames, kFrames };

  // Restores the checkpoint first when asked (durability). Throws when a run file cannot be created.
  explicit EdgeSystem(EdgeSystemSettings settings, WallClock clock = wall_clock_seconds,
                      EdgeDurability::BootIds boot_ids = random_boot_id);
  ~EdgeSystem();  // a last checkpoint and the outputs

  // A message that did not decode or broke the record rules: counted per topic and reason,
  // logged once per kind, then throttled.
  void reject(Topic topic, const std::string& why, size_t bytes);
  // `robot`: which mobile's topic it came on (0..robots()-1; one mobile: 0).
  KeyFrameVerdict receive_keyframe(const KeyFrameRecord& record, size_t bytes, int robot = 0);
  void skip_keyframes_through(uint64_t floor, int robot = 0) { session_->skip_keyframes_through(floor, robot); }
  // A relocalization request answered with an update, if there is one to give.
  std::optional<MapUpdateRecord> answer_frame(const FrameRecord& frame, size_t bytes, int robot = 0);
  std::optional<MapUpdateRecord> periodic_update(int robot = 0);
  // After Local-Mapping progressed: the update due now because a KeyFrame the mobile made is far
  // from the edge's (edge_slam/update_on_divergence; module/update_trigger.h), if any.
  std::optional<MapUpdateRecord> divergence_update(int robot = 0);
  int robots() const { return session_->robots(); }
  // Around publishing an update: the publish stamp it carries, then its figures and CSV row
  // (construction latency = build start -> serialised and handed over).
  void stamp_for_publishing(MapUpdateRecord& update) const;
  void published(const MapUpdateRecord& update, size_t bytes, double data_now, int robot = 0);

  KeyFrameAck ack(int robot = 0) { return durability_.ack(robot); }
  bool mapping_progressed(int robot = 0) const { return durability_.mapping_progressed(robot); }
  // "loop closed: ..." once per loop: logged, in the CSV, and returned for the loops topic.
  std::vector<std::string> new_loops(double data_now);
  // Maps of two robots joined since the last call: logged, in the CSV, returned for ~merges.
  // After a restore or a load, the file's merges come first, once, marked restored (the CSV's
  // "merge_restored"): a restarted edge's latched ~merges would otherwise stay empty although
  // the maps are joined, while its run files must not count them as merges of this run.
  std::vector<MergeEvent> new_merges(double data_now);
  // TF world -> robotN/map, once the robot's map is placed in the world.
  std::optional<Eigen::Isometry3d> T_world_robot(int robot) const { return session_->placement(robot).T_world_robot; }

  bool checkpoint(const char* why) { return durability_.checkpoint(why, clock_()); }
  bool save_map(const std::string& path, std::string* message);
  bool load_map(const std::string& path, std::string* message);

  Figures stats() const;
  // Every second and at shutdown: CSV flushed, metrics.json, the KeyFrames file; every
  // MemorySampleClock::kPeriodS also a "heap" row (split/memory_row.h) in the CSV.
  void write_outputs();

  const EdgeSystemSettings& settings() const { return settings_; }
  const EdgeSession& session() const { return *session_; }
  const EdgeDurability& durability() const { return durability_; }
  uint64_t malformed(Topic topic) const;
  uint64_t malformed() const { return malformed(Topic::kKeyFrames) + malformed(Topic::kFrames); }

 private:
  EventRow row(const char* event, double data_time) const;
  // The allocator's figures and the map objects alive beside the Global-Map's, at most every
  // MemorySampleClock::kPeriodS (wall): a leak shows apart from the map's growth. Then, with
  // EdgeSessionParams::release_free_heap, the free heap pages go back (the row's release_ms).
  void sample_memory();
  EdgeKeyFrames world_keyframes() const;

  EdgeSystemSettings settings_;
  WallClock clock_;
  RunRecorder recorder_;
  std::unique_ptr<EdgeSession> session_;
  EdgeDurability durability_;
  RejectionLog malformed_keyframes_{"rejecting a malformed message on 'keyframes'",
                                    "rejecting malformed messages on 'keyframes'"};
  RejectionLog malformed_frames_{"rejecting a malformed message on 'frames'", "rejecting malformed messages on 'frames'"};
  LogThrottle invalid_keyframe_log_{5.0}, refused_frame_log_{5.0}, write_error_log_{30.0};
  // What new_loops / new_merges have told. A loaded file's loops (which start afresh) were told
  // by the edge that saved it; its merges (the first of the list, EdgeSession::merges(&loaded))
  // are told again as restored: rebase_announcements() after a load. A list that shrank was
  // restarted with the modules (a reset): told again from its start.
  std::mutex announce_mutex_;
  size_t loops_announced_ = 0, merges_announced_ = 0;
  void rebase_announcements();
  mutable std::mutex figures_mutex_;
  std::vector<double> keyframe_latency_ms_, update_build_ms_, divergence_cm_;
  // (robot, seq) of updates divergence_update built and not yet published: the event CSV labels
  // them "divergence" (the wire kind is periodic: the mobile installs both alike).
  std::set<std::pair<int, uint64_t>> divergence_pending_;
  uint64_t keyframe_bytes_ = 0, update_bytes_ = 0, updates_sent_ = 0;
  std::vector<std::vector<double>> update_latency_by_robot_;  // build start -> published, ms
  std::vector<std::vector<double>> keyframe_latency_by_robot_;
  std::mutex write_mutex_;  // write_outputs: timer and destructor
  MemorySampleClock heap_clock_;  // wall clock; under write_mutex_
};

}  // namespace edge_slam
