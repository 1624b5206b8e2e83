// Test helper: keyframes with exact synthetic observations of known 3-D points, built
// directly as FrameFeatures (no images). Each physical point has its own random
// descriptor, and BoW is faked with one word / one direct-index node per physical point,
// so BoW searches and the keyframe database behave as with a perfect vocabulary.
#pragma once
#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/map_edit.h"

namespace edge_slam_test {
using namespace edge_slam;

inline PinholeCamera test_camera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  c.bf = 40;  // 8 cm virtual baseline
  c.th_depth = 4.0;
  return c;
}

inline std::shared_ptr<const ScalePyramid> test_pyramid() {
  static const auto p = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  return p;
}

struct World {
  std::vector<Eigen::Vector3d> points;
  cv::Mat descriptors;  // one row per physical point
  explicit World(std::vector<Eigen::Vector3d> pts, unsigned seed = 7) : points(std::move(pts)) {
    descriptors = cv::Mat(static_cast<int>(points.size()), 32, CV_8U);
    std::mt19937 rng(seed);
    for (int r = 0; r < descriptors.rows; ++r)
      for (int c = 0; c < 32; ++c) descriptors.at<uint8_t>(r, c) = static_cast<uint8_t>(rng() & 0xff);
  }
};

// What one keyframe sees: the physical ids of its keypoints (in order).
struct View {
  std::vector<size_t> physical;
};

// Keypoints of the points visible from T_cw (true pose), with depth when with_depth.
inline std::shared_ptr<const FrameFeatures> render(const World& w, const Eigen::Isometry3d& T_cw, bool with_depth,
                                                   View& view, const PinholeCamera& cam = test_camera()) {
  auto f = std::make_shared<FrameFeatures>();
  f->camera = cam;
  f->pyramid = test_pyramid();
  f->bounds = ImageBounds{0.f, static_cast<float>(cam.width), 0.f, static_cast<float>(cam.height)};
  std::vector<int> rows;
  for (size_t p = 0; p < w.points.size(); ++p) {
    const Eigen::Vector3d pc = T_cw * w.points[p];
    if (pc.z() < 0.1) continue;
    const Eigen::Vector2d uv = cam.project(pc);
    if (!f->bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y()))) continue;
    cv::KeyPoint k(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f, 0.f, 1.f, 0);
    f->keys.push_back(k);
    f->keys_un.push_back(k);
    const float z = static_cast<float>(pc.z());
    f->depth.push_back(with_depth ? z : -1.f);
    f->right_x.push_back(with_depth ? static_cast<float>(uv.x() - cam.bf / pc.z()) : -1.f);
    rows.push_back(static_cast<int>(p));
    view.physical.push_back(p);
  }
  f->descriptors = cv::Mat(static_cast<int>(rows.size()), 32, CV_8U);
  for (size_t i = 0; i < rows.size(); ++i) w.descriptors.row(rows[i]).copyTo(f->descriptors.row(static_cast<int>(i)));
  f->grid = FeatureGrid(f->keys_un, f->bounds);
  return f;
}

// Perfect-vocabulary BoW: word = node = physical point id.
inline void set_fake_bow(KeyFrame& kf, const View& view) {
  BowVector bow;
  FeatureVector fv;
  for (size_t i = 0; i < view.physical.size(); ++i) {
    bow[static_cast<WordId>(view.physical[i])] += 1.0 / view.physical.size();
    fv[static_cast<NodeId>(view.physical[i])].push_back(static_cast<uint32_t>(i));
  }
  kf.set_bow(std::move(bow), std::move(fv));
}

// A keyframe at `T_cw_estimate` rendered from `T_cw_true`, added to the map.
inline std::shared_ptr<KeyFrame> make_keyframe(Map& map, const World& w, const Eigen::Isometry3d& T_cw_true,
                                               const Eigen::Isometry3d& T_cw_estimate, bool with_depth, View& view) {
  const uint32_t id = map.new_keyframe_id();
  auto kf = std::make_shared<KeyFrame>(id, id, 0.1 * id, render(w, T_cw_true, with_depth, view), T_cw_estimate);
  set_fake_bow(*kf, view);
  map.add_keyframe(kf);
  return kf;
}

// A new map point for keypoint i of kf at `position` (descriptor from the keypoint).
inline std::shared_ptr<MapPoint> make_point(Map& map, const std::shared_ptr<KeyFrame>& kf, size_t i,
                                            const Eigen::Vector3d& position) {
  auto mp = std::make_shared<MapPoint>(map.new_map_point_id(), position, kf->id());
  mp->set_descriptor(kf->features().descriptor(i));
  map.add_map_point(mp);
  add_observation(kf, i, mp);
  return mp;
}

inline Eigen::Isometry3d look_from(const Eigen::Vector3d& center, double yaw) {
  // Camera looking along +z rotated by yaw about the world y axis; returns T_cw.
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
  T_wc.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_wc.translation() = center;
  return T_wc.inverse();
}

// Sum of squared pixel errors of every observation of good points by good keyframes.
inline double reprojection_error(const Map& map) {
  double e = 0;
  for (const auto& kf : map.keyframes()) {
    const auto pts = kf->map_points(map);
    const Eigen::Isometry3d T = kf->T_cw();
    for (size_t i = 0; i < pts.size(); ++i) {
      if (!pts[i]) continue;
      const Eigen::Vector3d pc = T * pts[i]->position();
      const Eigen::Vector2d uv = kf->features().camera.project(pc);
      e += (uv - Eigen::Vector2d(kf->features().keys_un[i].pt.x, kf->features().keys_un[i].pt.y)).squaredNorm();
    }
  }
  return e;
}

}  // namespace edge_slam_test
