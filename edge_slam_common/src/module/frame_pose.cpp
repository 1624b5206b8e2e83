#include "edge_slam/module/frame_pose.h"

#include "edge_slam/data/map_point.h"
#include "edge_slam/util/stage_clock.h"

namespace edge_slam {

PoseObservation pose_observation(const FrameFeatures& f, size_t i, const Eigen::Vector3d& point_world) {
  PoseObservation o;
  o.point_world = point_world;
  o.pixel = {f.keys_un[i].pt.x, f.keys_un[i].pt.y};
  o.right_x = f.right_x[i];
  o.inv_sigma2 = f.pyramid->inv_level_sigma2[f.keys_un[i].octave];
  return o;
}

int optimize_frame_pose(Frame& frame) {
  StageScope stage(TrackingStage::kPose);
  const FrameFeatures& f = frame.feat();
  std::vector<PoseObservation> obs;
  std::vector<size_t> keypoint_of;
  std::vector<bool> outlier;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp) continue;
    obs.push_back(pose_observation(f, i, mp->position()));
    keypoint_of.push_back(i);
    outlier.push_back(false);
  }
  Eigen::Isometry3d T_cw = frame.T_cw();
  const PoseOptimizationResult r = optimize_pose(f.camera, obs, T_cw, outlier);
  if (!r.ok) return -1;
  frame.set_pose(T_cw);
  for (size_t k = 0; k < keypoint_of.size(); ++k) frame.outliers[keypoint_of[k]] = outlier[k];
  return r.inliers;
}

int discard_outliers(Frame& frame) {
  int inliers = 0;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    if (!frame.map_points[i]) continue;
    if (frame.outliers[i]) {
      frame.map_points[i] = nullptr;
      frame.outliers[i] = false;
    } else if (frame.map_points[i]->num_observations() > 0) {
      ++inliers;
    }
  }
  return inliers;
}

}  // namespace edge_slam
