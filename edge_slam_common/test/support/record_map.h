// Test helper: a small map built directly from feature records (no images) — six KeyFrames
// along a line, consecutive ones sharing 60 map points — and its Local-Map update record.
#pragma once
#include <memory>
#include <random>

#include "edge_slam/io/map_records.h"
#include "edge_slam/sim/synthetic_camera.h"

namespace edge_slam {
namespace test_support {

inline PinholeCamera test_camera() { return synthetic_room_camera(30.0); }

// Six KeyFrames along a line; consecutive ones share map points (chain covisibility).
struct SyntheticMap {
  PinholeCamera camera = test_camera();
  std::shared_ptr<const ScalePyramid> pyramid = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  Map map;

  SyntheticMap() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(20, 620), v(20, 460), d(0.5f, 4.f);
    constexpr int kPerKf = 120, kPoints = 60 * 5 + kPerKf;
    for (uint32_t p = 0; p < kPoints; ++p)
      map.add_map_point(std::make_shared<MapPoint>(1000 + p, Eigen::Vector3d(0.01 * p, 0.5, 2.0), 0));
    for (uint32_t k = 0; k < 6; ++k) {
      FeatureRecord f;
      f.descriptors.create(kPerKf, 32, CV_8U);
      for (int i = 0; i < kPerKf; ++i) {
        f.keypoints.emplace_back(u(rng), v(rng), 31.f, 0.f, 0.f, i % 8);
        f.depth.push_back(i % 7 == 0 ? -1.f : d(rng));
        for (int b = 0; b < 32; ++b) f.descriptors.at<uint8_t>(i, b) = static_cast<uint8_t>(rng());
      }
      Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();
      T_cw.translation() = Eigen::Vector3d(-0.1 * k, 0, 0);
      auto kf = std::make_shared<KeyFrame>(k, 10 * k, 100.0 + k,
                                           features_from_record(f, to_camera_record(camera), camera, pyramid), T_cw);
      // KeyFrame k sees points [60k, 60k + 120): 60 shared with each neighbour.
      for (int i = 0; i < kPerKf; ++i) kf->set_map_point_id(i, 1000 + 60 * k + i);
      map.add_keyframe(kf);
    }
    for (const auto& kf : map.keyframes()) {
      const auto ids = kf->map_point_ids();
      for (size_t i = 0; i < ids.size(); ++i) map.map_point(ids[i])->add_observation(kf->id(), static_cast<int>(i));
    }
    for (const auto& kf : map.keyframes()) kf->update_connections(map);
  }

  MapUpdateRecord update() const {
    MapUpdateRecord u;
    for (const auto& kf : map.keyframes()) u.keyframes.push_back(to_record(*kf, map));
    for (const auto& mp : map.map_points())
      if (mp->num_observations() > 0) u.points.push_back(to_record(*mp));
    return u;
  }
};

}  // namespace test_support
}  // namespace edge_slam
