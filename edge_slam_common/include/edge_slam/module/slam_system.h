// Monolithic mode (our ORB-SLAM2 equivalent): Tracking in the caller's thread, Local-Mapping
// and Loop-Closing in their own threads, all on one Map. Tracking's new keyframes go to the
// local mapper's queue, the mapper's idle state feeds keyframe condition 2, processed
// keyframes go to the loop closer. Without local mapping it is tracking only.
// The trajectory is kept ORB-SLAM2 style: every tracked frame's pose relative to its
// reference keyframe, composed at the end with that keyframe's final pose (through the
// spanning tree when it was culled; data/trajectory_anchors.h), so loop and BA corrections
// reach every frame.
#pragma once
#include <memory>
#include <mutex>
#include <unordered_map>
#include <utility>
#include <vector>

#include "edge_slam/data/trajectory_anchors.h"
#include "edge_slam/module/mapping_threads.h"
#include "edge_slam/module/tracking.h"

namespace edge_slam {

struct SlamSystemOptions {
  bool local_mapping = true;
  bool loop_closing = true;  // needs local_mapping
  LocalMappingParams mapping;
  LoopClosingParams loop;
  // A last global BA once mapping has drained (finish()): every KeyFrame and point, as after a
  // loop. ORB-SLAM2 saves its trajectory without one; we offer it because the final map is what
  // the trajectory is composed from. 0 iterations = off.
  int final_full_ba_iterations = 0;
  // Deterministic replay (edge_slam_run --pace sync): when > 0, KeyFrame condition 2 sees the
  // mapper as busy for this many frames after each new KeyFrame instead of the thread's real
  // state, which depends on the machine's load. 0 = the real state (real time).
  int simulated_mapping_frames = 0;
};

class SlamSystem {
 public:
  SlamSystem(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& tracking_params,
             std::shared_ptr<const BowVocabulary> vocabulary, const SlamSystemOptions& options = {},
             RgbEncoding encoding = RgbEncoding::kBgr);
  ~SlamSystem();

  TrackingResult track_rgbd(const cv::Mat& color, const cv::Mat& depth, double stamp);
  TrackingResult track_frame(Frame frame);

  // Deterministic replay: waits up to timeout_s until Local-Mapping has processed every queued
  // KeyFrame and Loop-Closing (full BA included) is quiet, the threads keep running. Called
  // after each frame, it gives mapping all the time it needs, so a run does not depend on load.
  bool wait_until_idle(double timeout_s) const;

  // Waits up to timeout_s for the mapping queue to drain, loop closing to finish (full BA
  // included), then stops the threads. False when the wait timed out (work was cut short).
  bool finish(double timeout_s);

  // T_wc of every tracked frame (stamp, pose), from the current keyframe poses.
  std::vector<std::pair<double, Eigen::Isometry3d>> trajectory() const;

  Tracking& tracking() { return *tracking_; }
  const Map& map() const { return *map_; }
  std::shared_ptr<Map> map_ptr() const { return map_; }
  const LocalMapping* local_mapping() const { return threads_ ? &threads_->mapping() : nullptr; }
  const LoopClosing* loop_closing() const { return threads_ ? threads_->loop() : nullptr; }

 private:
  TrackingResult record(const TrackingResult& r, double stamp);
  void simulate_mapper_state();

  std::shared_ptr<Map> map_;
  std::shared_ptr<KeyFrameDatabase> database_;
  std::unique_ptr<Tracking> tracking_;
  std::unique_ptr<MappingThreads> threads_;  // null when tracking only
  bool finished_ = false;
  int simulated_mapping_frames_ = 0;
  int frames_since_keyframe_ = 1 << 30;
  int final_full_ba_iterations_ = 0;

  mutable std::mutex records_mutex_;
  std::vector<FrameAnchor> frames_;
  std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>> all_keyframes_;  // culled ones too
};

}  // namespace edge_slam
