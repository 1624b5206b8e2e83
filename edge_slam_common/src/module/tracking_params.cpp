#include "edge_slam/module/tracking_params.h"

#include <stdexcept>

namespace edge_slam {

OrbParams load_orb_params(const ConfigMap& cfg) {
  OrbParams p;
  p.num_features = cfg.get_int_or("orb/num_features", p.num_features, 50, 100000);
  p.scale_factor = static_cast<float>(cfg.get_double_or("orb/scale_factor", p.scale_factor, 1.01, 4.0));
  p.num_levels = cfg.get_int_or("orb/num_levels", p.num_levels, 1, 32);
  p.ini_fast_threshold = cfg.get_int_or("orb/ini_fast_threshold", p.ini_fast_threshold, 1, 255);
  p.min_fast_threshold = cfg.get_int_or("orb/min_fast_threshold", p.min_fast_threshold, 1, 255);
  return p;
}

KeyFrameDecisionParams load_keyframe_decision_params(const ConfigMap& cfg) {
  KeyFrameDecisionParams k;
  k.min_frames_after_relocalization =
      cfg.get_int_or("tracking/min_frames_after_relocalization", k.min_frames_after_relocalization, 0, 100000);
  k.max_frames_between_keyframes =
      cfg.get_int_or("tracking/max_frames_between_keyframes", k.max_frames_between_keyframes, 1, 100000);
  k.min_tracked_points = cfg.get_int_or("tracking/min_tracked_points", k.min_tracked_points, 0, 100000);
  k.ref_ratio = cfg.get_double_or("tracking/ref_ratio", k.ref_ratio, 0.0, 1.0);
  k.close_points_tracked = cfg.get_int_or("tracking/close_points_tracked", k.close_points_tracked, 0, 100000);
  k.close_points_new = cfg.get_int_or("tracking/close_points_new", k.close_points_new, 0, 100000);
  return k;
}

TrackingParams load_tracking_params(const ConfigMap& cfg) {
  TrackingParams p;
  p.keyframe = load_keyframe_decision_params(cfg);
  p.new_points_per_keyframe =
      cfg.get_int_or("tracking/new_points_per_keyframe", p.new_points_per_keyframe, 0, 100000);
  p.min_initial_keypoints = cfg.get_int_or("tracking/min_initial_keypoints", p.min_initial_keypoints, 1, 100000);
  p.min_inliers = cfg.get_int_or("tracking/min_inliers", p.min_inliers, 3, 100000);
  p.min_inliers_after_relocalization = cfg.get_int_or(
      "tracking/min_inliers_after_relocalization", p.min_inliers_after_relocalization, 3, 100000);
  p.conditions = cfg.get_choice<KeyFrameConditionSet>("tracking/keyframe_conditions", "all",
                                                      {{"all", KeyFrameConditionSet::kAll},
                                                       {"mobile", KeyFrameConditionSet::kMobile},
                                                       {"edge", KeyFrameConditionSet::kEdge}});
  p.reference_min_observations =
      cfg.get_int_or("tracking/reference_min_observations", p.reference_min_observations, 1, 1000);
  p.weak_pose_inlier_share =
      cfg.get_double_or("tracking/weak_pose_inlier_share", p.weak_pose_inlier_share, 0.0, 1.0);
  p.weak_pose_max_departure_m =
      cfg.get_double_or("tracking/weak_pose_max_departure", p.weak_pose_max_departure_m, 0.0, 10.0);
  using DepthPoints = TrackingParams::LastFrameDepthPoints;
  p.last_frame_depth_points = cfg.get_choice<DepthPoints>(
      "tracking/last_frame_depth_points", "off",
      {{"off", DepthPoints::kOff}, {"mobile", DepthPoints::kMobile}, {"on", DepthPoints::kOn}});
  p.max_local_keyframes = cfg.get_int_or("tracking/max_local_keyframes", p.max_local_keyframes, 1, 100000);
  return p;
}

TrackingParams for_host(TrackingParams p, TrackerHost host) {
  using D = TrackingParams::LastFrameDepthPoints;
  if (p.last_frame_depth_points == D::kMobile)
    p.last_frame_depth_points = host == TrackerHost::kMobile ? D::kOn : D::kOff;
  return p;
}

}  // namespace edge_slam
