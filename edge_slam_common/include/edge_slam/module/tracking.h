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
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/rolling_shutter.h"
#include "edge_slam/data/trajectory_anchors.h"
#include "edge_slam/feature/orb_extractor.h"
#include "edge_slam/module/local_map.h"
#include "edge_slam/module/relocalizer.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/stage_clock.h"

namespace edge_slam {

class BowVocabulary;

enum class TrackingState { kNotInitialized, kOk, kLost };
const char* to_string(TrackingState s);

// Why a frame was tracked the way it was: what a per-frame log needs to explain a failure
// (which search found the pose, how many matches each stage kept, how far the pose moved
// from the constant-velocity prediction, which KeyFrame conditions held).
struct TrackingDiagnostics {
  const char* path = "";          // init | motion | motion_wide | reference | relocalization | lost
  int last_frame_points = 0;      // motion model: the previous frame's points it can search for
  int initial_matches = 0;        // matches of the first search (motion model / BoW)
  int initial_inliers = 0;        // after the first pose optimisation
  int local_map_points = 0;       // local-map points projected into the frame
  int matches_before_final = 0;   // frame matches entering the local-map pose optimisation
  int reference_points = 0;       // condition (4)'s comparator: the reference KeyFrame's points
  uint32_t reference_kf_id = kNoId;  // the reference KeyFrame of the KeyFrame decision
  int tracked_close = 0, untracked_close = 0;  // condition (5)'s counts
  uint32_t keyframe_conditions = 0;  // KeyFrameConditionBits that held (see keyframe_decision.h)
  bool has_prediction = false;    // a constant-velocity prediction existed
  double prediction_error_m = 0;  // final camera centre vs the predicted one
  double prediction_error_deg = 0;
  bool weak_pose = false;         // too little support (tracking_params.h, weak_pose_*): no KeyFrame
  int last_frame_depth_points = 0;  // temporary points the last frame's depth lent (last_frame_depth_points.h)
  int depth_point_inliers = 0;      // ... inliers of the frame's final pose
};

// One line of key=value pairs (path, the match counts, the reference KeyFrame, the prediction
// error, the KeyFrame conditions): the split mobile's per-frame event row carries it, as the
// monolithic runner's frame_times.csv carries the same fields in columns.
std::string describe(const TrackingDiagnostics& d);

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
  bool input_rejected = false;    // the images were unusable: no frame was made (times are 0)
  TrackingDiagnostics diag;
  // Filled by MobileSession, for the final trajectory (frames re-anchored on the edge's
  // optimised KeyFrames, as ORB-SLAM2 saves its trajectory; data/trajectory_anchors.h): the
  // frame on its reference KeyFrame; for a new KeyFrame, its spanning-tree parent and pose
  // relative to it.
  std::optional<FrameAnchor> frame_anchor;
  std::optional<KeyFrameLink> keyframe_link;
};

struct TrackingCounters {
  int frames = 0;
  int frames_tracked = 0;
  int times_lost = 0;        // OK -> LOST transitions
  int relocalizations = 0;
  int keyframes_created = 0;
  int rejected_inputs = 0;
  int wide_motion_searches = 0;  // frames whose motion-model hypothesis needed the wide search too
  int weak_frames = 0;           // tracked frames whose pose the matches barely supported
};

// A pose found from the last frame's matches within a search window (motion model).
struct MotionHypothesis {
  float window = 0;
  int matches = 0, inliers = 0;  // inliers: map points only
  int depth_inliers = 0;         // the last frame's depth points left after the pose optimisation
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  std::vector<std::shared_ptr<MapPoint>> map_points;
  std::vector<bool> outliers;
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
  const Frame& last_frame() const { return last_frame_; }
  uint32_t reference_keyframe_id() const { return reference_kf_ ? reference_kf_->id() : kNoId; }
  const OrbExtractor& extractor() const { return extractor_; }
  // What the KeyFrame decision of the latest frame saw (zero before any decision / at initialisation).
  const KeyFrameDecisionInput& last_keyframe_decision() const { return last_decision_; }
  // Forget everything (map and database included): back to NOT_INITIALIZED.
  void reset();
  // After the map was cleared and rebuilt (a Local-Map update replacing the objects):
  // re-resolves the last frame's map points and the reference keyframe by id in the new
  // map, dropping what it no longer contains, so the motion model keeps working. With the map
  // as it was before (`old_map`), the last frame also moves with the correction the update
  // applied to its reference KeyFrame (ORB-SLAM2's UpdateLastFrame), so the next prediction
  // and the rolling-shutter velocity do not take the map correction for camera motion.
  // A point no longer there by its own id is followed to its replacement when `replaced_by`
  // names one (module/point_replacements.h: the edge fused it into another); returns how many.
  // Takes the map's update mutex; call it after the rebuild released it.
  int relink_after_map_update(const Map* old_map = nullptr,
                              const std::unordered_map<uint32_t, uint32_t>* replaced_by = nullptr);

 private:
  bool initialize(Frame& frame, std::string& why);
  bool track_with_motion_model(Frame& frame, TrackingDiagnostics& diag);
  bool track_reference_keyframe(Frame& frame, TrackingDiagnostics& diag);
  bool track_local_map(Frame& frame, int& inliers, TrackingDiagnostics& diag);
  // Rolling-shutter compensation with the motion just tracked, then a pose refinement.
  void recompensate_rolling_shutter(Frame& frame, const std::shared_ptr<const FrameFeatures>& measured);
  int search_local_points(Frame& frame, const LocalMap& local);
  bool decide_keyframe(const Frame& frame, int inliers, TrackingDiagnostics& diag) const;
  std::shared_ptr<KeyFrame> create_keyframe(Frame& frame, bool all_depth_points);
  // Moves the last frame with its reference KeyFrame and lends it its depth points (params).
  void predict_last_frame_pose(TrackingDiagnostics& diag);

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
  bool last_frame_weak_ = false;  // tracked, but its pose was weakly supported (see is_weak_pose)
  Eigen::Isometry3d last_relative_to_ref_ = Eigen::Isometry3d::Identity();  // T_last,ref
  bool has_velocity_ = false;
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();  // T_cur,last
  CameraVelocity velocity_per_second_;  // the same motion as a rate, for rolling-shutter compensation
  std::shared_ptr<KeyFrame> reference_kf_;
  uint64_t last_keyframe_frame_id_ = 0;
  bool relocalized_before_ = false;
  uint64_t last_relocalization_frame_id_ = 0;
  mutable KeyFrameDecisionInput last_decision_;

  // No per-frame history here: each TrackingResult carries its frame's times and the caller
  // keeps what it needs (the monolithic runner every frame's, the mobile a summary), so a
  // robot that tracks for hours does not grow by ~100 bytes a frame for figures nobody reads.
  TrackingCounters counters_;
};

}  // namespace edge_slam
