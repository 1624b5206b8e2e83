// The mobile side of Edge-SLAM without ROS (paper 4.4, 4.7): Tracking on the Local-Map; every
// new KeyFrame becomes a record (with the map points it created) in an outbox that a sender
// thread drains, so tracking never waits for the network; Local-Map updates from the edge go
// through the acceptance policy (eq. 1) and, when accepted, replace the Local-Map in linear
// time while tracking is paused; while lost, a processed Frame is offered every
// `relocalization_frame_period` seconds for edge assistance.
// Thread-safe: track(), apply_update() and reset() exclude each other (an update pauses
// tracking), the outbox is a queue, the rest are snapshots.
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_set>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/io/wire_records.h"
#include "edge_slam/module/map_point_culling.h"
#include "edge_slam/module/map_update_policy.h"
#include "edge_slam/module/tracking.h"
#include "edge_slam/util/bounded_queue.h"
#include "edge_slam/util/wall_clock.h"

namespace edge_slam {

struct MobileSessionParams {
  // Which robot this is when one edge serves several (util/robot_ids.h): its KeyFrame and point
  // ids come from its own ranges. 0 = the one mobile of the paper (the ids it always had).
  int robot_index = 0;
  MapUpdatePolicyParams policy;             // ITC 300 ms, LMU 6
  double relocalization_frame_period = 0.5; // seconds between Frames sent while lost
  size_t outbox_capacity = 2000;            // KeyFrame records waiting for the sender
  size_t local_map_cap = 50;                // KeyFrames kept in the Local-Map (oldest dropped beyond)
  // KeyFrame conditions on the mobile (edge_slam/mobile_keyframe_pacing). The paper checks 3-5
  // here and 1-2 on the edge only (kNone); then the mobile, which has no Local-Mapping to wait
  // for, asks for a KeyFrame whenever (4) or (5) holds: on fr1 that is 3 frames of 4, each one
  // uploaded, mostly refused by the edge's condition 2, its points lost with it. kEdge also
  // checks 1-2 here, (2) reading the edge's Local-Mapping state from its acknowledgements
  // (KeyFrameAck.mapped_seq: done with every KeyFrame sent): the KeyFrame rate of a monolithic
  // ORB-SLAM2, whose tracker reads its own mapper's state the same way. The edge still decides.
  enum class KeyFramePacing { kEdge, kNone };
  KeyFramePacing keyframe_pacing = KeyFramePacing::kEdge;
  // A periodic update refused by rule (d) only (a KeyFrame was just made) is kept and re-checked
  // on each frame for this many seconds instead of being dropped: bursts of KeyFrames are short,
  // and the next update is a whole period away. 0 = refuse at once (the paper's behaviour).
  double update_retry_window = 0.5;
  // How an accepted update is installed (edge_slam/update_install). kReplace: the paper's full
  // replacement (4.6.1). An update holds only update_size KeyFrames and only what the edge had
  // when it started building it; kKeepNewer puts back the mobile's KeyFrames made since, kMerge
  // every KeyFrame of the Local-Map the update does not hold (module/update_carry_over.h: with
  // their points, moved by the update's correction), so the places tracking turns back to stay
  // mapped; the cap then drops the oldest of those first, never the update's own.
  enum class UpdateInstall { kReplace, kKeepNewer, kMerge };
  UpdateInstall update_install = UpdateInstall::kMerge;
  // ORB-SLAM2 culls a new point that tracking predicted in view but matched in fewer than 25% of
  // those frames; only tracking has those counts, and in the split it runs here. true: each
  // KeyFrame record names the recent points that failed the test (module/map_point_culling.h)
  // and the edge culls them; false: the paper's record, the edge culls by observers only.
  bool refute_unfound_points = true;
  MapPointCullingParams point_culling;  // local_mapping/point_*: the edge's own rules
  // After each installed update, give the heap's free pages back to the system
  // (util/heap_release.h): the replaced Local-Map's memory otherwise stays with the allocator,
  // fragmented, and the mobile's RSS creeps up although its in-use memory is flat.
  bool release_heap_after_update = true;
};

class ConfigMap;
// The "edge_slam:" section of config/slam.yaml (defaults are the paper's); throws with the key
// and the valid range on a bad value.
MobileSessionParams load_mobile_session_params(const ConfigMap& cfg);

// Why the mobile made its KeyFrames, and what its Local-Map updates kept of what tracking used:
// the figures that tell whether the split's KeyFrame rate and update content are right.
struct MobileKeyFrameStats {
  uint64_t made = 0;
  uint64_t fewer_than_reference = 0;  // condition (4) held
  uint64_t needs_close_points = 0;    // condition (5) held
  uint64_t weak_tracking = 0;         // condition (2)'s weak-tracking clause held
  uint64_t reference_mobile_made = 0; // the decision's reference was a KeyFrame this mobile made
  uint64_t inliers_sum = 0, reference_points_sum = 0;
  uint64_t points_refuted = 0;        // recent points tracking found too rarely, named in the records
};
struct MobileUpdateStats {
  uint64_t installed = 0;
  // Of the map points the last frame tracked before each install, how many the new Local-Map
  // still holds (by id): what tracking keeps across the swap.
  uint64_t tracked_points_before = 0, tracked_points_kept = 0;
  // Of the others, how many were followed to the point the edge fused them into (point_replacements.h).
  uint64_t tracked_points_followed = 0;
  double min_kept_share = 1.0;
  uint64_t mobile_keyframes_dropped = 0;  // mobile-made KeyFrames the swap removed from the Local-Map
  uint64_t keyframes_carried = 0;         // Local-Map KeyFrames the update did not hold, kept (merge / keep_newer)
  // How far each update moved the map under the camera: the correction at the last frame's
  // reference KeyFrame (camera centre displacement), the largest and the sum over the updates.
  double max_correction_m = 0, sum_correction_m = 0;
  // ... the same reference KeyFrame's rotation (deg), and the median displacement of the points
  // the last frame tracked that the new Local-Map still holds (what tracking is aligned to: when
  // it exceeds the reference's, the update moved the map under the camera non-rigidly), largest
  // over the updates.
  double max_reference_rotation_deg = 0, max_tracked_point_shift_m = 0;
  // release_heap_after_update: calls made, how many gave memory back, their total wall time.
  uint64_t heap_releases = 0, heap_releases_freeing = 0;
  double heap_release_ms = 0, max_heap_release_ms = 0;
};

struct UpdateOutcome {
  UpdateDecision decision = UpdateDecision::kAccept;
  double stage_ms = 0;          // objects built and linked off-line (tracking runs meanwhile)
  double rebuild_ms = 0;        // Local-Map replaced by the staged one (tracking paused)
  size_t keyframes = 0, map_points = 0;
  std::string error;            // a record the rebuild refused (the Local-Map is unchanged)
};

class MobileSession {
 public:
  // Tracking runs with the KeyFrame conditions of params.keyframe_pacing. `clock` stamps the
  // records' created_wall (the edge's backlog rule and the transmit latency read it).
  MobileSession(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& tracking,
                std::shared_ptr<const BowVocabulary> vocabulary, const MobileSessionParams& params,
                RgbEncoding encoding = RgbEncoding::kRgb, WallClock clock = wall_clock_seconds);

  TrackingResult track(const cv::Mat& color, const cv::Mat& depth, double stamp);
  // Decision kDeferred: kept and re-checked by track(); take_deferred_outcome() tells how it ended.
  UpdateOutcome apply_update(const MapUpdateRecord& update, double now);
  // Once per deferred update, after the track() that applied or finally refused it: its seq and outcome.
  std::optional<std::pair<uint64_t, UpdateOutcome>> take_deferred_outcome();
  void count_invalid_update();
  // The edge's acknowledged Local-Mapping progress (KeyFrameAck.mapped_seq), any thread; and
  // whether its Local-Mapping holds another robot's KeyFrame (one edge, several mobiles: then
  // it is not idle for this robot's condition 2 either).
  void on_edge_progress(uint64_t mapped_seq, bool mapper_busy_elsewhere = false);
  // A processed frame for relocalization assistance, when lost and the period has elapsed.
  std::optional<FrameRecord> take_relocalization_frame(double now);
  // Paper 4.7.4: queue the newest KeyFrame again with its reset flag (the edge resets on it),
  // then clear the Local-Map and restart initialisation. False when there is no KeyFrame yet
  // (nothing to reset on the edge either).
  bool reset();

  BoundedQueue<KeyFrameRecord>& outbox() { return outbox_; }
  size_t outbox_size() const { return outbox_.size(); }
  void set_updates_enabled(bool enabled);
  bool updates_enabled() const;
  MapUpdateCounters update_counters() const;
  double time_constraint() const;
  size_t local_map_keyframes() const { return map_->num_keyframes(); }
  size_t local_map_peak() const;           // most KeyFrames the Local-Map ever held
  size_t local_map_cap() const { return params_.local_map_cap; }
  uint64_t keyframes_dropped_by_cap() const;
  size_t local_map_points() const { return map_->num_map_points(); }
  TrackingState state() const;
  TrackingCounters tracking_counters() const;
  std::shared_ptr<const Map> local_map() const { return map_; }
  uint64_t keyframes_sent() const;
  MobileKeyFrameStats keyframe_stats() const;
  MobileUpdateStats update_stats() const;
  // Every KeyFrame id tracking created, in order (4 bytes each): the delivery accounting.
  std::vector<uint32_t> keyframe_ids_created() const;

 private:
  void on_new_keyframe(const std::shared_ptr<KeyFrame>& kf);
  void note_local_map_size();
  struct PendingUpdate {
    uint64_t seq = 0;
    uint64_t last_keyframe_seq = 0;  // the newest KeyFrame seq the edge had when it built the update
    StagedUpdate staged;
  };
  TrackingSnapshot snapshot(double now) const;                 // mutex_ held
  void install(PendingUpdate& pending, UpdateOutcome& out);    // mutex_ held, update accepted
  // Instrumentation of the frames after an install (mutex_ held): frames tracked since the last
  // install (1000 before any), the latest frame's inliers, those of the frame before the install.
  int frames_since_update_ = 1000, last_inliers_ = 0, inliers_before_update_ = 0;
  // mutex_ held; returns the update it decided on (to be freed outside the lock), if any
  std::shared_ptr<PendingUpdate> recheck_deferred_update(double now);

  WallClock clock_;
  PinholeCamera camera_;
  std::shared_ptr<const BowVocabulary> vocabulary_;
  MobileSessionParams params_;
  std::shared_ptr<const ScalePyramid> pyramid_;  // for KeyFrames rebuilt from updates
  std::shared_ptr<Map> map_;
  std::shared_ptr<KeyFrameDatabase> database_;
  BoundedQueue<KeyFrameRecord> outbox_;

  mutable std::mutex mutex_;  // held by track(), apply_update(), reset()
  Tracking tracking_;
  MapUpdatePolicy policy_;
  double last_stamp_ = 0;
  double last_keyframe_stamp_ = 0;
  bool keyframe_since_update_ = false;
  uint64_t next_keyframe_seq_ = 1;
  std::atomic<uint64_t> edge_mapped_seq_{0};
  std::atomic<bool> edge_busy_elsewhere_{false};
  uint64_t next_frame_seq_ = 1;
  double last_relocalization_frame_time_ = -1e300;
  std::optional<KeyFrameRecord> newest_keyframe_;
  std::shared_ptr<KeyFrame> newest_created_;  // made during the current track() call
  size_t local_map_peak_ = 0;
  uint64_t dropped_by_cap_ = 0;
  std::shared_ptr<PendingUpdate> deferred_update_;  // refused by (d) only, re-checked per frame
  double deferred_since_ = 0;
  std::optional<std::pair<uint64_t, UpdateOutcome>> deferred_outcome_;
  std::vector<uint32_t> created_ids_;
  std::vector<uint64_t> created_seqs_;  // the record seq of each created_ids_ entry
  std::unordered_set<uint32_t> created_set_;
  MobileKeyFrameStats keyframe_stats_;
  MobileUpdateStats update_stats_;
};

}  // namespace edge_slam
