#include "edge_slam/solve/pnp_solver.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <cmath>

namespace edge_slam {
namespace {

constexpr size_t kMinCorrespondences = 6;  // EPnP RANSAC draws 5; one more to have a check

bool is_finite_correspondence(const PoseObservation& o) {
  return o.point_world.allFinite() && o.pixel.allFinite();
}

Eigen::Isometry3d from_rvec_tvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(tvec, t);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

}  // namespace

PnpResult solve_pnp_ransac(const PinholeCamera& cam, const std::vector<PoseObservation>& obs,
                           const PnpParams& params) {
  PnpResult result;
  result.inliers.assign(obs.size(), false);

  std::vector<size_t> used;  // indices of the finite correspondences handed to OpenCV
  std::vector<cv::Point3d> object_points;
  std::vector<cv::Point2d> image_points;
  for (size_t i = 0; i < obs.size(); ++i) {
    if (!is_finite_correspondence(obs[i])) continue;
    used.push_back(i);
    object_points.emplace_back(obs[i].point_world.x(), obs[i].point_world.y(), obs[i].point_world.z());
    image_points.emplace_back(obs[i].pixel.x(), obs[i].pixel.y());
  }
  if (used.size() < kMinCorrespondences) {
    result.message = "too few finite correspondences: " + std::to_string(used.size());
    return result;
  }

  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> ransac_inliers;
  bool found = false;
  try {
    found = cv::solvePnPRansac(object_points, image_points, K, cv::noArray(), rvec, tvec, false,
                               params.ransac_iterations, static_cast<float>(params.ransac_reprojection_px),
                               params.ransac_confidence, ransac_inliers, cv::SOLVEPNP_EPNP);
  } catch (const cv::Exception& e) {
    result.message = std::string("solvePnPRansac threw: ") + e.what();
    return result;
  }
  if (!found || rvec.empty() || tvec.empty()) {
    result.message = "RANSAC found no pose";
    return result;
  }
  Eigen::Isometry3d T_cw = from_rvec_tvec(rvec, tvec);
  if (!T_cw.matrix().allFinite()) {
    result.message = "RANSAC pose is not finite";
    return result;
  }

  std::vector<bool> is_outlier(obs.size(), true);
  for (int k : ransac_inliers) is_outlier[used[static_cast<size_t>(k)]] = false;
  int num_inliers = static_cast<int>(ransac_inliers.size());

  if (params.refine) {
    const PoseOptimizationResult refined = optimize_pose(cam, obs, T_cw, is_outlier);
    if (!refined.ok) {
      result.T_cw = T_cw;
      result.message = "refinement failed: " + refined.message;
      return result;
    }
    num_inliers = refined.inliers;
  }

  result.T_cw = T_cw;
  for (size_t i = 0; i < obs.size(); ++i) result.inliers[i] = !is_outlier[i];
  result.num_inliers = num_inliers;
  result.ok = num_inliers >= params.min_inliers;
  result.message = (result.ok ? "accepted, inliers " : "rejected, inliers ") +
                   std::to_string(num_inliers) + "/" + std::to_string(obs.size());
  return result;
}

}  // namespace edge_slam
