#include "edge_slam/module/triangulation.h"

#include <Eigen/SVD>
#include <cmath>

#include "edge_slam/data/map_edit.h"
#include "edge_slam/match/keyframe_search.h"

namespace edge_slam {
namespace {

constexpr double kChi2Mono = 5.991, kChi2Stereo = 7.815;
constexpr double kMaxCosParallaxWithoutDepth = 0.9998;

Eigen::Vector3d normalized_ray(const FrameFeatures& f, size_t i) {
  const cv::KeyPoint& k = f.keys_un[i];
  return {(k.pt.x - f.camera.cx) / f.camera.fx, (k.pt.y - f.camera.cy) / f.camera.fy, 1.0};
}

// Cosine of the parallax the depth sensor's virtual baseline gives at this keypoint
// (> 1 when the keypoint has no depth, so it never wins).
double depth_parallax_cos(const FrameFeatures& f, size_t i) {
  if (!f.has_depth(i)) return 2.0;
  return std::cos(2.0 * std::atan2(0.5 * f.camera.baseline(), f.depth[i]));
}

Eigen::Vector3d linear_triangulation(const Eigen::Vector3d& xn1, const Eigen::Isometry3d& T1,
                                     const Eigen::Vector3d& xn2, const Eigen::Isometry3d& T2, bool& ok) {
  const Eigen::Matrix<double, 3, 4> P1 = T1.matrix().topRows<3>();
  const Eigen::Matrix<double, 3, 4> P2 = T2.matrix().topRows<3>();
  Eigen::Matrix4d A;
  A.row(0) = xn1.x() * P1.row(2) - P1.row(0);
  A.row(1) = xn1.y() * P1.row(2) - P1.row(1);
  A.row(2) = xn2.x() * P2.row(2) - P2.row(0);
  A.row(3) = xn2.y() * P2.row(2) - P2.row(1);
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d h = svd.matrixV().col(3);
  ok = std::abs(h(3)) > 1e-12;
  return ok ? Eigen::Vector3d(h.head<3>() / h(3)) : Eigen::Vector3d::Zero();
}

bool reprojects_well(const FrameFeatures& f, size_t i, const Eigen::Vector3d& p_c) {
  if (!(p_c.z() > 0)) return false;
  const cv::KeyPoint& k = f.keys_un[i];
  const Eigen::Vector2d uv = f.camera.project(p_c);
  const double ex = uv.x() - k.pt.x, ey = uv.y() - k.pt.y;
  const double s2 = f.pyramid->level_sigma2[k.octave];
  if (f.right_x[i] >= 0) {
    const double er = uv.x() - f.camera.bf / p_c.z() - f.right_x[i];
    return ex * ex + ey * ey + er * er <= kChi2Stereo * s2;
  }
  return ex * ex + ey * ey <= kChi2Mono * s2;
}

}  // namespace

bool triangulate_pair(const KeyFrame& kf1, size_t i1, const KeyFrame& kf2, size_t i2, Eigen::Vector3d& x_w) {
  const FrameFeatures& f1 = kf1.features();
  const FrameFeatures& f2 = kf2.features();
  const Eigen::Isometry3d T1 = kf1.T_cw(), T2 = kf2.T_cw();
  const Eigen::Vector3d xn1 = normalized_ray(f1, i1), xn2 = normalized_ray(f2, i2);
  const Eigen::Vector3d ray1 = T1.linear().transpose() * xn1, ray2 = T2.linear().transpose() * xn2;
  const double cos_rays = ray1.dot(ray2) / (ray1.norm() * ray2.norm());
  const double cos_depth1 = depth_parallax_cos(f1, i1), cos_depth2 = depth_parallax_cos(f2, i2);
  const double cos_depth = std::min(cos_depth1, cos_depth2);
  const bool depth1 = f1.has_depth(i1), depth2 = f2.has_depth(i2);

  if (cos_rays < cos_depth && cos_rays > 0 && (depth1 || depth2 || cos_rays < kMaxCosParallaxWithoutDepth)) {
    bool ok = false;
    x_w = linear_triangulation(xn1, T1, xn2, T2, ok);
    if (!ok) return false;
  } else if (depth1 && cos_depth1 < cos_depth2) {
    x_w = kf1.unproject_world(i1);
  } else if (depth2 && cos_depth2 < cos_depth1) {
    x_w = kf2.unproject_world(i2);
  } else {
    return false;  // too little parallax and no usable depth
  }
  if (!x_w.allFinite()) return false;
  if (!reprojects_well(f1, i1, T1 * x_w) || !reprojects_well(f2, i2, T2 * x_w)) return false;

  // Scale consistency: the distance ratio must agree with the pyramid level ratio.
  const double dist1 = (x_w - kf1.camera_center()).norm(), dist2 = (x_w - kf2.camera_center()).norm();
  if (dist1 <= 0 || dist2 <= 0) return false;
  const double ratio_dist = dist2 / dist1;
  const double ratio_octave = f1.pyramid->scale_factors[f1.keys_un[i1].octave] /
                              f2.pyramid->scale_factors[f2.keys_un[i2].octave];
  const double ratio_factor = 1.5 * f1.pyramid->scale_factor;
  return !(ratio_dist * ratio_factor < ratio_octave || ratio_dist > ratio_octave * ratio_factor);
}

std::vector<std::shared_ptr<MapPoint>> triangulate_new_points(Map& map, const std::shared_ptr<KeyFrame>& kf,
                                                              const TriangulationParams& params,
                                                              const std::function<bool()>& interrupt) {
  std::vector<std::shared_ptr<MapPoint>> created;
  if (!kf->has_bow() || kf->is_bad()) return created;
  const Eigen::Vector3d c1 = kf->camera_center();
  const double baseline = kf->features().camera.baseline();
  const auto neighbours = kf->best_covisibles(params.num_covisibles);
  for (size_t n = 0; n < neighbours.size(); ++n) {
    if (n > 0 && interrupt && interrupt()) break;
    const auto other = map.keyframe(neighbours[n]);
    if (!other || other->is_bad() || !other->has_bow()) continue;
    if ((other->camera_center() - c1).norm() < baseline) continue;  // depth beats this baseline
    const auto pairs = search_for_triangulation(*kf, *other, map, fundamental_matrix(*kf, *other));
    for (const auto& [i1, i2] : pairs) {
      Eigen::Vector3d x_w;
      if (!triangulate_pair(*kf, i1, *other, i2, x_w)) continue;
      auto mp = std::make_shared<MapPoint>(map.new_map_point_id(), x_w, kf->id());
      add_observation(kf, i1, mp);
      add_observation(other, i2, mp);
      map.add_map_point(mp);
      mp->update_descriptor(map);
      mp->update_normal_and_depth(map);
      created.push_back(std::move(mp));
    }
  }
  return created;
}

}  // namespace edge_slam
