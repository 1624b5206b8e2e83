// Loop-Closing (ORB-SLAM2's LoopClosing; on the edge in the split system): its own thread
// takes the keyframes local mapping has processed, detects loop candidates (LoopDetector),
// verifies them geometrically (verify_loop), corrects the loop with local mapping paused
// (correct_loop) and then runs a full bundle adjustment in a background thread; a newer
// loop in the same map aborts a running full BA. With several maps in one (several robots),
// loops and merges are serialised per map: a correction pauses Local-Mapping and moves
// KeyFrames for the map(s) it concerns only, each map has its own full BA, and the other
// robots' mapping, loop detection and full BA go on. Each closed loop is logged as
//   "loop closed: KF <current> <-> KF <loop>, <n> matches".
#pragma once
#include <atomic>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/module/loop_corrector.h"
#include "edge_slam/module/loop_detector.h"
#include "edge_slam/module/loop_verifier.h"
#include "edge_slam/util/bounded_queue.h"

namespace edge_slam {

class LocalMapping;

struct LoopClosingParams {
  LoopDetectorParams detector;
  LoopVerifierParams verifier;
  LoopCorrectionParams correction;
  bool full_ba = true;
  int full_ba_iterations = 10;  // ORB-SLAM2: 10
  bool full_ba_in_background = true;  // false: run it inline (tests)
  double mapper_stop_timeout_s = 10.0;
  size_t queue_capacity = 1000;
};

struct LoopEvent {
  uint32_t current_kf_id = 0, loop_kf_id = 0;
  int matches = 0;
  LoopCorrectionReport correction;
};

// Two maps joined (several robots, module/robot_frames.h): of the current and the loop
// KeyFrame's groups, the one with the higher id was moved into the other's coordinates by
// T_into_from (group 0, the world, never moves), then the loop was corrected.
struct MergeEvent {
  uint32_t current_kf_id = 0, loop_kf_id = 0;
  int group_from = 0, group_into = 0;
  int matches = 0;
  Eigen::Isometry3d T_into_from = Eigen::Isometry3d::Identity();
  LoopCorrectionReport correction;
};

class LoopClosing {
 public:
  // local_mapping may be null (then nothing is paused: single-threaded use and tests).
  LoopClosing(std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
              LocalMapping* local_mapping, const LoopClosingParams& params = {});
  ~LoopClosing();

  // Several maps in one (module/robot_frames.h), set before start(): the group of a KeyFrame.
  // A verified loop between KeyFrames of two groups is a merge: every KeyFrame and point of the
  // group with the higher id moves rigidly into the other's coordinates, then
  // the loop is corrected (points fused, essential graph) and a full BA runs, as for a loop.
  // on_merge runs with Map::update_mutex() held, right after the move (the owner re-labels the
  // groups there, so no KeyFrame is received in between with the old transform); it must take
  // no lock but leaf locks. Unset: one group, no merges (one robot).
  std::function<int(uint32_t kf_id)> group_of;
  std::function<void(int from, int into, const Eigen::Isometry3d& T_into_from)> on_merge;
  // Runs with Map::update_mutex() held before and after each change of the map's geometry by
  // loop closing (a merge, a loop correction, a full BA applied): the owner follows the moves
  // (several robots: RobotFrames::follow_anchors).
  std::function<void()> on_map_moved;

  void start();
  void shutdown(bool drain = true);  // also waits for a running full BA
  void insert_keyframe(const std::shared_ptr<KeyFrame>& kf);
  // Detection + verification + correction for one keyframe; true when a loop was closed.
  bool process_keyframe(const std::shared_ptr<KeyFrame>& kf);
  // Waits (bounded) for the queue to drain and a full BA to finish.
  bool wait_until_idle(double timeout_s) const;

  // The loop detector's history for the edge's map file, and its restoration (before any
  // KeyFrame of the restored map is processed). Safe beside the loop thread.
  void save_detector_to(std::vector<LoopGroupRecord>& groups, std::vector<LoopRobotRecord>& robots) const;
  void restore_detector(const std::vector<LoopGroupRecord>& groups, const std::vector<LoopRobotRecord>& robots);

  int loops_closed() const;
  std::vector<LoopEvent> loops() const;
  std::vector<MergeEvent> merges() const;
  int full_ba_runs() const;
  std::vector<double> detection_times_ms() const;   // detection + verification per keyframe
  std::vector<double> correction_times_ms() const;         // pause + correction, per loop or merge
  std::vector<double> correction_locked_times_ms() const;  // of which under the Global-Map's lock
  // ... its longest hold: how long the other robots' mapping waits at most (with several robots
  // the fusion's search runs unlocked between two holds)
  std::vector<double> correction_longest_lock_times_ms() const;
  std::vector<double> full_ba_times_ms() const;

 private:
  void run();
  struct FullBa {
    int map = 0;  // the map it adjusts (the group of its loop KeyFrame)
    uint32_t loop_kf_id = 0;
    std::atomic<bool> abort{false}, done{false};
    std::thread thread;
  };
  void run_full_ba(FullBa& job);
  // Moves every KeyFrame of group `from` and its points by T_into_from; the caller holds the map update mutex.
  void move_group(int from, const Eigen::Isometry3d& T_into_from);
  void start_full_ba(uint32_t kf_id, int map);
  // Aborts and joins the full BAs of these maps (every map: empty); joins finished ones.
  void stop_full_bas(const std::vector<int>& maps);
  int map_of(uint32_t kf_id) const { return group_of ? group_of(kf_id) : 0; }

  std::shared_ptr<Map> map_;
  std::shared_ptr<KeyFrameDatabase> database_;
  LocalMapping* local_mapping_;
  LoopClosingParams params_;
  // The loop thread's detection against a save; held while the detector reads the map and the
  // database (their own data locks, never the map's update mutex): never take it under a map lock.
  mutable std::mutex detector_mutex_;
  LoopDetector detector_;
  BoundedQueue<std::shared_ptr<KeyFrame>> queue_;
  std::thread thread_;
  std::atomic<bool> busy_{false};
  std::atomic<uint64_t> submitted_{0}, completed_{0};  // as LocalMapping's: no idle window after a pop
  std::atomic<bool> running_{false};                   // the thread is consuming the queue
  bool debug_;  // EDGE_SLAM_DEBUG_LOOP set: one line per keyframe on detection

  std::mutex full_ba_mutex_;
  std::list<FullBa> full_bas_;                 // started by the loop thread, at most one per map
  std::atomic<int> full_bas_running_{0};
  std::atomic<bool> shutting_down_{false};     // shutdown(false): running full BAs abort

  mutable std::mutex stats_mutex_;
  std::vector<LoopEvent> loops_;
  std::vector<MergeEvent> merges_;
  uint64_t merge_passes_ = 0;
  int full_ba_runs_ = 0;
  std::vector<double> detect_ms_, correct_ms_, correct_locked_ms_, correct_longest_lock_ms_, full_ba_ms_;
};

}  // namespace edge_slam
