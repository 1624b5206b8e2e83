// Local-Mapping (ORB-SLAM2's LocalMapping; on the edge in the split system): its own thread
// takes new keyframes from a queue and, per keyframe, (1) finishes its insertion (BoW, point
// observations, normals/descriptors, covisibility, spanning tree, keyframe database),
// (2) culls recent map points, (3) triangulates new points with its covisibles, and when
// no other keyframe waits (4) fuses duplicates with the neighbours, (5) runs local BA
// (aborted when a keyframe arrives) and (6) culls redundant keyframes. Processed keyframes
// are handed to on_keyframe_processed (the loop closer's queue).
// Loop correction pauses it with request_stop() / wait_until_stopped() / release(); with several
// maps in one (several robots, module/robot_frames.h) only the KeyFrames of the maps being
// corrected wait, and the other robots' KeyFrames go on being mapped.
#pragma once
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <unordered_set>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/module/local_mapping_params.h"
#include "edge_slam/module/map_point_culling.h"
#include "edge_slam/util/bounded_queue.h"

namespace edge_slam {

class BowVocabulary;

struct LocalMappingStats {
  int keyframes_processed = 0;
  int keyframes_skipped = 0;  // bad / erased while queued
  int points_culled = 0;
  int points_refuted = 0;  // of those: culled because the mobile's tracking found them too rarely
  int points_created = 0;
  int points_fused = 0;
  int keyframes_culled = 0;
  int local_ba_runs = 0;
  int local_ba_aborted = 0;
  int local_ba_failed = 0;
  // KeyFrames mapped while another map's KeyFrames were held back by a pause (several robots:
  // one robot's mapping going on during another's loop correction or merge).
  int keyframes_mapped_beside_a_pause = 0;
  // Window sizes summed over the local BA runs (divide by local_ba_runs for the mean).
  long long local_ba_free_keyframes = 0;
  long long local_ba_fixed_keyframes = 0;
  long long local_ba_observations = 0;
};

class LocalMapping {
 public:
  LocalMapping(std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
               std::shared_ptr<const BowVocabulary> vocabulary, const LocalMappingParams& params = {});
  ~LocalMapping();

  void start();  // launches the thread
  // Closes the queue; with drain the remaining keyframes are processed first. Joins.
  void shutdown(bool drain = true);

  // Queues a keyframe (already inserted in the map by tracking) and aborts a running local BA.
  void insert_keyframe(const std::shared_ptr<KeyFrame>& kf);
  // Points a mobile's tracking found too rarely (its KeyFrame records' refuted points): culled at
  // the next KeyFrame's point culling if still on probation there, else forgotten. Any thread.
  void refute_points(const std::vector<uint32_t>& ids);
  // Synchronous processing of one keyframe (what the thread does per keyframe; tests).
  void process_keyframe(const std::shared_ptr<KeyFrame>& kf);

  // Nothing queued, held back or being processed. A KeyFrame held back by a pause keeps it busy:
  // condition 2 paces every robot on the one Local-Mapping (module/edge_keyframe_decision.h).
  bool idle() const { return idle_; }
  size_t queued() const { return queue_.size(); }
  // Waits (bounded) until every KeyFrame inserted so far has been processed.
  bool wait_until_idle(double timeout_s) const;

  // Several maps in one (module/robot_frames.h), set before start(): the map of a KeyFrame.
  // Unset: one map.
  std::function<int(uint32_t kf_id)> group_of;

  // Pause protocol for loop correction. request_stop(maps) holds back the KeyFrames of those maps
  // (of every map when `maps` is empty or group_of is unset): they stay queued in order and the
  // other maps' KeyFrames are mapped meanwhile. wait_until_stopped() returns true once no
  // KeyFrame of a held-back map is being processed (or the thread is not running).
  // release(maps) lifts the request made with the same maps. Requests stack: a correction and a
  // full BA of different maps may each hold theirs.
  void request_stop(const std::vector<int>& maps = {});
  bool wait_until_stopped(double timeout_s) const;
  void release(const std::vector<int>& maps = {});
  // A request is in force and no KeyFrame of a held-back map is being processed.
  bool stopped() const;

  // Keyframe condition 2 (Tracking::set_mapper_idle) and the loop closer's input.
  std::function<void(bool idle)> on_idle_changed;
  std::function<void(const std::shared_ptr<KeyFrame>&)> on_keyframe_processed;
  // Every KeyFrame inserted, once Local-Mapping is done with it (processed, skipped or evicted).
  std::function<void(const std::shared_ptr<KeyFrame>&)> on_keyframe_done;
  // The keyframes culled as redundant, out of the map by now (the edge accounts for every
  // KeyFrame it accepted, and places the frames that referred to them through their parent).
  std::function<void(const std::vector<std::shared_ptr<KeyFrame>>&)> on_keyframes_culled;

  LocalMappingStats stats() const;
  std::vector<double> process_times_ms() const;  // whole keyframe processing
  std::vector<double> local_ba_times_ms() const;

 private:
  void run();
  void set_idle(bool idle);
  bool new_keyframes_waiting() const { return queue_.size() > 0; }
  void finish_insertion(const std::shared_ptr<KeyFrame>& kf);
  void run_local_ba(const std::shared_ptr<KeyFrame>& kf);
  // The next KeyFrame to map: the oldest held-back one whose map is free again, else the queue's
  // (held back, and the next one looked for, when its map is paused). Null: none for now.
  std::shared_ptr<KeyFrame> next_keyframe();
  int map_of(const std::shared_ptr<KeyFrame>& kf) const;
  bool held_back_locked(int map) const;  // pause_mutex_ held
  void release_all();

  std::shared_ptr<Map> map_;
  std::shared_ptr<KeyFrameDatabase> database_;
  std::shared_ptr<const BowVocabulary> vocabulary_;
  LocalMappingParams params_;
  BoundedQueue<std::shared_ptr<KeyFrame>> queue_;
  RecentMapPoints recent_;
  std::mutex refuted_mutex_;
  std::unordered_set<uint32_t> refuted_;  // refute_points(), consumed by the next cull
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> busy_{false};
  std::atomic<bool> idle_{true};
  std::atomic<bool> abort_ba_{false};
  // KeyFrames handed in / finished (processed, skipped or evicted from the queue): idle waits
  // compare them, so the moment between a pop and the start of its processing is not "idle".
  std::atomic<uint64_t> submitted_{0}, completed_{0};

  static constexpr int kEveryMap = -1000;  // a request that holds back every map
  mutable std::mutex pause_mutex_;
  mutable std::condition_variable pause_cv_;
  std::multiset<int> paused_maps_;     // one entry per map per request in force
  bool finished_ = false;              // the thread has left its loop (shutdown)
  bool processing_ = false;            // a KeyFrame is being mapped ...
  int processing_map_ = 0;             // ... of this map
  std::deque<std::shared_ptr<KeyFrame>> held_;  // popped while their map was paused; mapping thread only
  std::atomic<bool> drain_held_{true};          // shutdown(false) drops them with the queue

  mutable std::mutex stats_mutex_;
  LocalMappingStats stats_;
  std::vector<double> process_ms_, local_ba_ms_;
};

}  // namespace edge_slam
