// Tracking settings and their loading from config/slam.yaml ("orb:" and "tracking:").
#pragma once
#include "edge_slam/feature/orb_params.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/module/keyframe_decision.h"

namespace edge_slam {

struct TrackingParams {
  KeyFrameDecisionParams keyframe;
  KeyFrameConditionSet conditions = KeyFrameConditionSet::kAll;
  int min_initial_keypoints = 500;          // ORB-SLAM2 RGB-D initialisation
  int min_inliers = 30;                     // local map tracking success
  int min_inliers_after_relocalization = 50;
  int new_points_per_keyframe = 100;        // closest points always made into map points
  int max_local_keyframes = 80;
  // Reference keyframe's points for condition (4) count an observation with depth twice
  // (ORB-SLAM2, needed with local mapping); tracking-only runs keep plain counts so that an
  // always-idle "mapper" does not turn every frame into a keyframe.
  bool depth_counts_twice = true;
  // Condition (4) counts the reference keyframe's points seen by at least this many
  // keyframes. ORB-SLAM2 uses 3 (2 while the map has <= 2 keyframes), relying on local
  // mapping to fuse observations; without a mapper points gain observations only from the
  // keyframes that track them, so 2 keeps (4) meaningful.
  int reference_min_observations = 2;
  // A tracked frame whose final pose keeps fewer than this share of the matches it was optimised
  // on is weakly supported (motion blur, a wrong prediction): it makes no KeyFrame, and the next
  // frame does not trust its velocity alone. 0 = off (ORB-SLAM2 has no such gate).
  double weak_pose_inlier_share = 0.2;
  // Also weakly supported: a frame whose pose left the constant-velocity prediction by more than
  // this (metres) while it tracks fewer close points than condition (5)'s close_points_tracked
  // (ORB-SLAM2's "tracking is weak"). On the synthetic look-away turn such a frame (62-65 inliers,
  // 3.5-4.8 cm from a prediction that was right) became a KeyFrame on the mobile, which has no
  // local BA to pull it back, and the frames after it tracked on its points 4 cm off for seconds.
  // 0 = off (ORB-SLAM2, the paper).
  double weak_pose_max_departure_m = 0.0;  // off: 0.025 lost tracking in 2 of 4 synthetic split runs (config/slam.yaml)
  // The last frame, when it is not a KeyFrame, lends the next frame's motion-model search
  // temporary points from its depth (ORB-SLAM2's localization-mode "visual odometry" points;
  // module/last_frame_depth_points.h). kMobile: only where the mapper is remote (the split's
  // mobile), resolved by for_host(). kOff = ORB-SLAM2's SLAM mode, the paper.
  enum class LastFrameDepthPoints { kOff, kMobile, kOn };
  LastFrameDepthPoints last_frame_depth_points = LastFrameDepthPoints::kOff;
};

// Where the tracker runs: with its own mapper (monolithic) or on the split's mobile.
enum class TrackerHost { kMonolithic, kMobile };
// The settings a tracker on `host` uses: "mobile"-only choices become on or off.
TrackingParams for_host(TrackingParams p, TrackerHost host);

OrbParams load_orb_params(const ConfigMap& cfg);          // "orb:" section, defaults if absent
// KeyFrame conditions 1-5 of the "tracking:" section: the tracker's, and the edge's 1-2.
KeyFrameDecisionParams load_keyframe_decision_params(const ConfigMap& cfg);
TrackingParams load_tracking_params(const ConfigMap& cfg);  // "tracking:" section (conditions included)

}  // namespace edge_slam
