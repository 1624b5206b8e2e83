#include "edge_slam/io/new_point_position.h"

#include <cmath>

#include "edge_slam/camera/pinhole_camera.h"

namespace edge_slam {

std::optional<Eigen::Vector3d> back_project(const CameraRecord& camera, const Eigen::Isometry3d& T_wc, double x,
                                            double y, double z) {
  if (!(z > 0.0) || !std::isfinite(z) || !(camera.fx > 0.0) || !(camera.fy > 0.0)) return std::nullopt;
  PinholeCamera pinhole;  // a record's keypoints are undistorted: its intrinsics are all it takes
  pinhole.fx = camera.fx;
  pinhole.fy = camera.fy;
  pinhole.cx = camera.cx;
  pinhole.cy = camera.cy;
  return T_wc * pinhole.unproject(x, y, z);
}

std::optional<Eigen::Vector3d> back_projected_keypoint(const KeyFrameRecord& r, size_t kp_index) {
  const FeatureRecord& f = r.features;
  if (kp_index >= f.size() || kp_index >= f.depth.size()) return std::nullopt;
  const cv::Point2f& pt = f.keypoints[kp_index].pt;
  return back_project(r.camera, r.T_wc, pt.x, pt.y, f.depth[kp_index]);
}

}  // namespace edge_slam
