// The edge side of Edge-SLAM without ROS (paper 4.5, 4.7.3-4.7.5): the Global-Map with
// Local-Mapping and Loop-Closing threads; received KeyFrame records are always taken (never
// blocking the receiver) and inserted if KeyFrame conditions 1-2 hold; the Local-Map Update
// Module packs the `update_size` most recently inserted KeyFrames with all their map points;
// the Relocalization Map Update Module answers a Frame with its KeyFrame-database candidates
// plus the KeyFrames connected to each. A KeyFrame flagged `reset` clears the Global-Map.
#pragma once
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <deque>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/trajectory_anchors.h"
#include "edge_slam/io/wire_records.h"
#include "edge_slam/module/edge_keyframe_decision.h"
#include "edge_slam/module/keyframe_decision.h"
#include "edge_slam/module/keyframe_receipts.h"
#include "edge_slam/module/late_keyframe_anchor.h"
#include "edge_slam/module/mapping_threads.h"
#include "edge_slam/module/module_metrics.h"
#include "edge_slam/module/robot_frames.h"
#include "edge_slam/module/update_trigger.h"

namespace edge_slam {

class BowVocabulary;
class ConfigMap;

// After load_map, new edge points start this far past the saved allocator: points made after
// the save may be in the mobile's Local-Map and come back, so their ids are never reused.
// Larger than what Local-Mapping makes between two checkpoints (~1000 points per KeyFrame).
inline constexpr uint32_t kPointIdGapAfterRestore = 1u << 22;

struct EdgeSessionParams {
  // Mobiles served (issue #16): robot r sends KeyFrames with ids of its own (util/robot_ids.h).
  // 1 = the paper's one mobile; with more, maps of robots that see the same place are merged
  // (module/robot_frames.h) and a reset clears only the resetting robot's current map.
  int robots = 1;
  int update_size = 6;                      // KeyFrames per Local-Map update (paper: 6)
  // Which KeyFrames a periodic update carries. kNewest: the update_size most recently inserted
  // (paper 4.5). kCovisible: the newest one and the KeyFrames the Global-Map sees most points in
  // common with it, i.e. what the camera is looking at now, even when the mobile turned back to
  // a place it mapped earlier (the newest alone then miss it, and the mobile maps it again).
  enum class UpdateContent { kNewest, kCovisible };
  UpdateContent update_content = UpdateContent::kCovisible;
  // Conditions 1-2, the same predicates and "tracking:" settings as the tracker's (one rule).
  KeyFrameDecisionParams keyframe;
  // Points made by a KeyFrame that conditions 1-2 refused are kept aside (at most this many)
  // until a later inserted KeyFrame observes them: the mobile goes on tracking them by id, and
  // without them the edge would lose those observations and triangulate duplicates instead.
  size_t pending_point_capacity = 50000;
  // Condition 2 paces KeyFrames arriving live. One created more than this many seconds ago
  // (by its created_wall stamp; mobile and edge clocks synchronised) is backlog from a link
  // outage or an edge restart: it is queued for Local-Mapping instead, or the map would lose
  // the whole stretch the mobile tracked meanwhile. 0 = always apply condition 2 (paper).
  double late_keyframe_age = 1.0;
  // A KeyFrame the mobile made after a correction moved its parent, before an update told it,
  // follows its parent's correction (module/late_keyframe_anchor.h); false = inserted as received (the paper).
  bool reanchor_late_keyframes = true;
  // The edge's process gives its heap's free pages back to the system at each memory reading
  // (EdgeSystem, every MemorySampleClock::kPeriodS; util/heap_release.h): the BA problems of
  // Local-Mapping and the full BAs are freed into memory glibc otherwise keeps (10-minute long
  // run: 357 of 486 MB of arena kept free). Long runs: mean RSS 9% lower back to back, the peak
  // (a BA between two releases) not (docs/benchmarks/2026-12-07/edge_heap_release). false = leave
  // it to the allocator.
  bool release_free_heap = true;
  size_t neighbours_per_candidate = 10;     // relocalization update: connected KeyFrames kept
  size_t max_update_keyframes = 50;         // relocalization update cap = the mobile's Local-Map cap
  double update_period = 5.0;               // seconds between periodic Local-Map updates
  // An update before the timer when a KeyFrame the mobile made is far from the edge's (module/update_trigger.h).
  UpdateTriggerParams update_trigger;
  bool loop_closing = true;
  LocalMappingParams mapping;
  LoopClosingParams loop;
};
// "edge_slam:" and "tracking:" sections of config/slam.yaml.
EdgeSessionParams load_edge_session_params(const ConfigMap& cfg);

// Where every KeyFrame accepted since the last reset went: still in the Global-Map, or culled
// as redundant by Local-Mapping. Nothing else may happen to one (a lost KeyFrame is a bug).
// `received` is every id taken since the last reset: those not inserted were rejected by
// condition 1 / 2 (or invalid), which accounts for them too.
struct KeyFrameAccount {
  std::vector<uint32_t> inserted, culled, in_map, received;  // sorted ids
};

enum class KeyFrameVerdict { kInserted, kDuplicate, kRejectedAfterRelocalization, kRejectedMapperBusy, kInvalid, kReset };
const char* to_string(KeyFrameVerdict v);

struct EdgeCounters {
  uint64_t received = 0, inserted = 0, duplicates = 0, rejected_condition1 = 0, rejected_condition2 = 0;
  uint64_t late_keyframes = 0;  // backlog KeyFrames exempted from condition 2 (late_keyframe_age)
  uint64_t invalid = 0, resets = 0, updates_built = 0, relocalization_updates_built = 0;
  uint64_t foreign_ids = 0;  // of them invalid: ids of another robot than the sender (util/robot_ids.h)
  uint64_t last_seq = 0;  // highest KeyFrame seq received (acknowledged in updates)
  uint64_t received_seq = 0;  // every seq up to this one received (delivery acknowledgement)
  uint64_t mapped_seq = 0;    // every seq up to this one decided and, if inserted, through Local-Mapping
  bool mapper_busy_elsewhere = false;  // Local-Mapping holds another robot's KeyFrame (several mobiles)
  uint64_t pending_points_adopted = 0;  // points of refused KeyFrames taken in by a later one
  uint64_t weak_tracking_inserted = 0;  // inserted while Local-Mapping was busy: condition 2's weak clause
  uint64_t reanchored_after_correction = 0;  // made before the mobile heard of a correction (late_keyframe_anchor.h)
  uint64_t updates_on_divergence = 0;  // of updates_built: sent before the timer (module/update_trigger.h)
};

class EdgeSession {
 public:
  EdgeSession(const PinholeCamera& camera, int pyramid_levels, float scale_factor,
              std::shared_ptr<const BowVocabulary> vocabulary, const EdgeSessionParams& params = {});
  ~EdgeSession();

  // `now`: wall-clock seconds (condition 2 exempts backlog KeyFrames by their age, edge_keyframe_decision.h).
  // `robot`: which mobile sent it (0..robots-1); its ids must be that robot's (foreign: kInvalid).
  KeyFrameVerdict receive_keyframe(const KeyFrameRecord& record, double now, std::string* error = nullptr,
                                   int robot = 0);
  // The mobile will never send a seq <= floor again (module/keyframe_delivery.h).
  void skip_keyframes_through(uint64_t floor, int robot = 0);
  // Every KeyFrame seq up to this one has been decided and, when inserted, processed by
  // Local-Mapping: acknowledged to the mobile as "Local-Mapping idle" for its condition 2.
  uint64_t mapped_seq(int robot = 0) const;
  // Nullopt until a KeyFrame was inserted. Updates are expressed in the robot's own frame.
  std::optional<MapUpdateRecord> build_local_map_update(double now, int robot = 0);
  // How far (camera centre, m) the edge has any KeyFrame the robot made since its last update
  // from where the mobile has it: local BA and corrections the mobile has not heard of. 0 when
  // none is known.
  double mobile_divergence_m(int robot = 0) const;
  // The same update as build_local_map_update, built now if that divergence makes one due
  // (module/update_trigger.h); `divergence`, if given, receives it.
  std::optional<MapUpdateRecord> build_update_on_divergence(double now, int robot = 0, double* divergence = nullptr);
  std::optional<MapUpdateRecord> build_relocalization_update(const FrameRecord& frame, double now,
                                                             std::string* error = nullptr, int robot = 0);
  // Waits (bounded) for Local-Mapping and Loop-Closing to finish what is queued.
  bool wait_until_idle(double timeout_s) const;

  // Global-Map persistence (io/map_file.h). save_map snapshots the map under the locks and
  // writes outside them (atomically); load_map reads and checks the file first, then replaces
  // the map, the KeyFrame database and the de-duplication state, restarting the mapping
  // threads. Both throw std::runtime_error with the reason; a failed load keeps the old map.
  // save_map returns, per robot, the received seq the file holds everything up to (what is now
  // durable). With several robots the file holds each robot's deliveries and where its maps are
  // (merges included: their placement and the merge history, so merges() goes on from the
  // file's); load_map refuses a file of another number of robots.
  std::vector<uint64_t> save_map(const std::string& path) const;
  void load_map(const std::string& path);

  EdgeCounters counters(int robot = 0) const;
  int robots() const { return static_cast<int>(robots_.size()); }
  std::shared_ptr<const Map> global_map() const { return map_; }
  int loops_closed() const;
  std::vector<LoopEvent> loops() const;
  // Oldest first, those of a loaded file included; `loaded`, when given, gets how many of them came
  // from the file last loaded (they come first), read under the same lock: a load between two
  // separate reads would mislabel them.
  std::vector<MergeEvent> merges(size_t* loaded = nullptr) const;
  // Where the robot's map is: its group and, once placed, TF world -> robotN/map.
  RobotPlacement placement(int robot) const { return frames_.placement(robot); }
  const RobotFrames& frames() const { return frames_; }
  KeyFrameAccount keyframe_account(int robot = 0) const;
  // The Global-Map's KeyFrame poses and, for each KeyFrame Local-Mapping culled since the last
  // reset or load, its parent and pose relative to it then: what the final trajectory is
  // composed from (data/trajectory_anchors.h). Culled links do not survive load_map.
  EdgeKeyFrames keyframe_poses() const;
  bool mapping_idle() const;
  // Local-Mapping / Loop-Closing counters and per-call timings since the last reset.
  ModuleFigures module_figures() const;

 private:
  void start_modules();
  void stop_modules();
  // One mobile's side of the session: its deliveries, conditions 1-2, updates, counters.
  struct RobotState {
    std::unordered_set<uint32_t> seen_ids;
    KeyFrameReceipts receipts;  // survives a reset: the mobile's seqs go on
    // Every KeyFrame id inserted since the last reset, in insertion order: the newest make the
    // periodic update; all of them are the accounting (4 bytes per KeyFrame on the edge).
    std::vector<uint32_t> inserted_ids;
    uint64_t last_inserted_frame_id = 0;
    bool any_inserted = false;
    uint64_t last_relocalization_frame_id = 0;
    bool relocalization_sent = false;
    uint64_t next_update_seq = 1;
    EdgeCounters counters;
    // Points of refused KeyFrames, by id, oldest first (bounded by pending_point_capacity),
    // in the robot's own frame (moved into the Global-Map's when adopted).
    std::unordered_map<uint32_t, std::shared_ptr<MapPoint>> pending_points;
    std::deque<uint32_t> pending_order;
    // The robot's KeyFrames as received since the last update was built (none before it is
    // used: module/late_keyframe_anchor.h).
    std::unordered_map<uint32_t, MobileKeyFrameView> mobile_views;
    // Largest distance so far between a parent KeyFrame's camera on the edge and where the mobile had it when it
    // made a child (local BA and corrections since the last update): logged when it grows past 3 cm.
    double largest_parent_divergence_m = 0.03;
    std::optional<double> last_update_time;  // `now` of the last update built (periodic or relocalization)
  };
  void reset_locked(int robot);
  void clear_robot(RobotState& rs);
  void restore_robot(int robot, const RobotMapSection& section);  // load_map, under mutex_
  std::optional<MapUpdateRecord> build_local_map_update_locked(RobotState& rs, double now, int robot);
  // The largest distance of any KeyFrame from the mobile's view, and of those update_trigger.moves
  // counts, in one pass; mutex_ held.
  struct Divergence {
    double all = 0.0, counted = 0.0;
  };
  Divergence mobile_divergence_locked(const RobotState& rs, int robot) const;
  MapUpdateRecord pack_update(const std::vector<std::shared_ptr<KeyFrame>>& kfs, int robot) const;
  bool multi() const { return robots_.size() > 1; }

  PinholeCamera camera_;
  std::shared_ptr<const ScalePyramid> pyramid_;
  std::shared_ptr<const BowVocabulary> vocabulary_;
  EdgeSessionParams params_;
  std::shared_ptr<Map> map_;
  std::shared_ptr<KeyFrameDatabase> database_;
  // Replaced on a reset and a load (under mutex_); a reader copies the pointer under mutex_ and
  // may then wait on it without the lock (a stopped module returns from a wait at once).
  std::shared_ptr<MappingThreads> modules_;
  std::shared_ptr<MappingThreads> modules() const;

  mutable std::mutex mutex_;  // receive / build / reset
  std::vector<RobotState> robots_;
  std::vector<MergeEvent> merges_loaded_;  // the merges of the file last loaded (the live ones are the modules')
  std::vector<MergeEvent> merges_locked() const;  // mutex_ held
  RobotFrames frames_;
  uint64_t transform_passes_ = 0;  // MapPoint::transform_once passes of received points
  // Corrections applied to the map (loop, merge, full BA; LoopClosing::on_map_moved, called and
  // read under the map's update mutex).
  uint64_t map_moves_ = 0;
  mutable std::mutex culled_mutex_;        // culled_* are written by the Local-Mapping thread
  std::vector<uint32_t> culled_ids_;
  std::vector<KeyFrameLink> culled_links_;  // of the KeyFrames culled since the last reset or load
  mutable std::mutex mapping_seq_mutex_;    // written by the Local-Mapping thread too
  std::map<uint32_t, uint64_t> in_mapping_;  // inserted KeyFrame id -> seq, until Local-Mapping is done with it
  void keep_pending_points(RobotState& rs, const KeyFrameRecord& r);
};

}  // namespace edge_slam
