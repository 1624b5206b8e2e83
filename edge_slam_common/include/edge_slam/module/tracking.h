// RGB-D tracking (ORB-SLAM2's state machine), working on whatever Map it is given: the
// full map (monolithic) or the mobile's Local-Map (split).
//   NOT_INITIALIZED -> first frame with enough keypoints: one keyframe, map points from
//                      every keypoint with valid depth.
//   OK   -> constant-velocity motion model (or reference keyframe by BoW), pose-only
//           optimisation, then local map tracking and a second optimisation; keyframe
//           decision; a new keyframe gets new close-depth map points.
//   LOST -> relocalization on every frame until it succeeds.
// New keyframes are inserted into the map (observations, covisibility, spanning tree,
// keyframe database) and then handed to on_new_keyframe (the local mapper's queue).
#pragma once
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/rolling_shutter.h"
#include "edge_slam/feature/orb_extractor.h"
#include "edge_slam/module/local_map.h"
#include "edge_slam/module/relocalizer.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/stage_clock.h"

namespace edge_slam {

class BowVocabulary;

enum class TrackingState { kNotInitialized, kOk, kLost };
const char* to_string(TrackingState s);

struct TrackingResult {
  TrackingState state = TrackingState::kNotInitialized;
  bool pose_valid = false;        // T_cw is a tracked pose of this frame
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
  uint64_t frame_id = 0;
  int keypoints = 0;
  int inliers = 0;
  bool new_keyframe = false;
  bool relocalized = false;
  double time_ms = 0;             // wall time: frame construction (ORB) + tracking
  double cpu_ms = 0;              // CPU time of this thread for the same work
  TrackingStageTimes stages;      // the same split by stage (extract, match, pose, local map, KeyFrame)
  std::string message;            // why tracking failed / the input was rejected
  // Filled by MobileSession, for the final trajectory (frames re-anchored on the edge's
  // optimised KeyFrames, as ORB-SLAM2 saves its trajectory): the reference KeyFrame and the
  // frame's pose relative to it; for a new KeyFrame, its spanning-tree parent and pose relative to it.
  uint32_t reference_kf_id = kNoId;
  Eigen::Isometry3d T_ref_c = Eigen::Isometry3d::Identity();
  uint32_t keyframe_id = kNoId, keyframe_parent_id = kNoId;
  Eigen::Isometry3d T_parent_kf = Eigen::Isometry3d::Identity();
};

struct TrackingCounters {
  int frames = 0;
  int frames_tracked = 0;
  int times_lost = 0;        // OK -> LOST transitions
  int relocalizations = 0;
  int keyframes_created = 0;
  int rejected_inputs = 0;
};

class Tracking {
 public:
  // vocabulary may be null: then the reference-keyframe fallback projects the last
  // frame's points with a wide window instead of BoW matching, and relocalization is off.
  Tracking(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& params,
           std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
           std::shared_ptr<const BowVocabulary> vocabulary,
           RgbEncoding encoding = RgbEncoding::kBgr);

  // Never throws for bad input: it is reported in the result (state unchanged, or LOST).
  TrackingResult track_rgbd(const cv::Mat& color, const cv::Mat& depth, double stamp);
  // Tracks a frame built by the caller (tests, pre-extracted features).
  TrackingResult track_frame(Frame frame);

  // Receives every new keyframe after it was inserted into the map.
  std::function<void(const std::shared_ptr<KeyFrame>&)> on_new_keyframe;
  // Injected by the local mapper (keyframe condition 2); true while nothing runs it.
  void set_mapper_idle(bool idle) { mapper_idle_ = idle; }
  // Replace the relocalizer (e.g. one that asks the edge); null disables relocalization.
  void set_relocalizer(std::shared_ptr<Relocalizer> r) { relocalizer_ = std::move(r); }

  TrackingState state() const { return state_; }
  const TrackingCounters& counters() const { return counters_; }
  const std::vector<double>& frame_times_ms() const { return times_ms_; }      // wall
  const std::vector<double>& frame_cpu_times_ms() const { return cpu_times_ms_; }
  const std::vector<TrackingStageTimes>& frame_stage_times() const { return stage_times_; }
  const Frame& last_frame() const { return last_frame_; }
  uint32_t reference_keyframe_id() const { return reference_kf_ ? reference_kf_->id() : kNoId; }
  const OrbExtractor& extractor() const { return extractor_; }
  // Forget everything (map and database included): back to NOT_INITIALIZED.
  void reset();
  // After the map was cleared and rebuilt (a Local-Map update replacing the objects):
  // re-resolves the last frame's map points and the reference keyframe by id in the new
  // map, dropping what it no longer contains, so the motion model keeps working.
  // Takes the map's update mutex; call it after the rebuild released it.
  void relink_after_map_update();

 private:
  bool initialize(Frame& frame, std::string& why);
  bool track_with_motion_model(Frame& frame);
  bool track_reference_keyframe(Frame& frame);
  bool track_local_map(Frame& frame, int& inliers);
  // Rolling-shutter compensation with the motion just tracked, then a pose refinement.
  void recompensate_rolling_shutter(Frame& frame, const std::shared_ptr<const FrameFeatures>& measured);
  void search_local_points(Frame& frame, const LocalMap& local);
  bool decide_keyframe(const Frame& frame, int inliers) const;
  std::shared_ptr<KeyFrame> create_keyframe(Frame& frame, bool all_depth_points);
  void predict_last_frame_pose();

  PinholeCamera camera_;
  TrackingParams params_;
  OrbExtractor extractor_;
  RgbEncoding encoding_;
  std::shared_ptr<Map> map_;
  std::shared_ptr<KeyFrameDatabase> database_;
  std::shared_ptr<const BowVocabulary> vocabulary_;
  std::shared_ptr<Relocalizer> relocalizer_;
  std::atomic<bool> mapper_idle_{true};

  TrackingState state_ = TrackingState::kNotInitialized;
  uint64_t next_frame_id_ = 0;
  Frame last_frame_;
  bool last_frame_tracked_ = false;
  Eigen::Isometry3d last_relative_to_ref_ = Eigen::Isometry3d::Identity();  // T_last,ref
  bool has_velocity_ = false;
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();  // T_cur,last
  CameraVelocity velocity_per_second_;  // the same motion as a rate, for rolling-shutter compensation
  std::shared_ptr<KeyFrame> reference_kf_;
  uint64_t last_keyframe_frame_id_ = 0;
  bool relocalized_before_ = false;
  uint64_t last_relocalization_frame_id_ = 0;

  TrackingCounters counters_;
  std::vector<double> times_ms_;
  std::vector<double> cpu_times_ms_;
  std::vector<TrackingStageTimes> stage_times_;
};

}  // namespace edge_slam
