// Map clear + rebuild must restore exactly the links built incrementally.
#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

using namespace edge_slam;

namespace {

PinholeCamera test_camera() {
  PinholeCamera c = synthetic_room_camera(30.0);
  c.fx = c.fy = 500;
  c.th_depth = 3.2;
  return c;
}

std::shared_ptr<const FrameFeatures> random_features(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> ux(0, 640), uy(0, 480);
  std::vector<cv::KeyPoint> keys(n);
  for (auto& k : keys) k = cv::KeyPoint(ux(rng), uy(rng), 31.f, 0.f, 0.f, 0);
  cv::Mat desc(static_cast<int>(n), 32, CV_8U);
  cv::randu(desc, 0, 255);
  auto pyr = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  return FrameFeatures::build(test_camera(), pyr, keys, desc, depth);
}

struct Snapshot {
  std::map<uint32_t, std::map<uint32_t, int>> weights;
  std::map<uint32_t, std::map<uint32_t, int>> observations;
  std::map<uint32_t, uint32_t> parents;
  std::map<uint32_t, std::set<uint32_t>> children;
};

Snapshot snapshot(const Map& map) {
  Snapshot s;
  for (const auto& kf : map.keyframes()) {
    s.weights[kf->id()] = kf->connection_weights();
    s.parents[kf->id()] = kf->parent_id();
    s.children[kf->id()] = kf->children();
  }
  for (const auto& mp : map.map_points()) s.observations[mp->id()] = mp->observations();
  return s;
}

// KeyFrame k observes map points [40k, 40k + 100): neighbours share 60, second
// neighbours 20, third neighbours nothing.
void build_six(Map& map, std::vector<std::shared_ptr<KeyFrame>>& kfs,
               std::vector<std::shared_ptr<MapPoint>>& mps) {
  std::mt19937 rng(7);
  for (uint32_t i = 0; i < 300; ++i) mps.push_back(std::make_shared<MapPoint>(i, Eigen::Vector3d(0, 0, 2), 0));
  for (const auto& mp : mps) map.add_map_point(mp);
  for (uint32_t k = 0; k < 6; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = -0.1 * k;
    auto kf = std::make_shared<KeyFrame>(k, k * 10, k * 0.3, random_features(100, rng), T);
    map.add_keyframe(kf);
    for (uint32_t j = 0; j < 100; ++j) {
      const uint32_t mp_id = 40 * k + j;
      kf->set_map_point_id(j, mp_id);
      mps[mp_id]->add_observation(k, static_cast<int>(j));
    }
    kf->update_connections(map);
    kfs.push_back(kf);
  }
}

}  // namespace

TEST(Map, IncrementalGraphIsAsDesigned) {
  Map map;
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<std::shared_ptr<MapPoint>> mps;
  build_six(map, kfs, mps);
  EXPECT_EQ(map.num_keyframes(), 6u);
  EXPECT_EQ(map.num_map_points(), 300u);
  EXPECT_EQ(kfs[2]->weight(1), 60);
  EXPECT_EQ(kfs[2]->weight(0), 20);
  EXPECT_EQ(kfs[2]->weight(5), 0);
  EXPECT_EQ(kfs[3]->parent_id(), 2u);
  EXPECT_EQ(kfs[0]->parent_id(), kNoId);
  EXPECT_EQ(kfs[0]->children(), std::set<uint32_t>({1}));
  EXPECT_EQ(kfs[2]->ordered_neighbours(), std::vector<uint32_t>({1, 3, 0, 4}));
  EXPECT_EQ(mps[45]->observations(), (std::map<uint32_t, int>{{0, 45}, {1, 5}}));
  EXPECT_EQ(map.new_keyframe_id(), 6u);
  EXPECT_EQ(map.new_map_point_id(), 300u);
}

TEST(Map, ClearAndRebuildRestoresLinks) {
  Map map;
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<std::shared_ptr<MapPoint>> mps;
  build_six(map, kfs, mps);
  const Snapshot before = snapshot(map);

  // Forget everything that rebuild must re-derive, including the spanning tree of half.
  map.clear();
  EXPECT_EQ(map.num_keyframes(), 0u);
  for (const auto& mp : mps) mp->clear_observations();
  for (const auto& kf : kfs) {
    kf->clear_connections();
    kf->clear_children();
    if (kf->id() % 2) kf->set_parent(kNoId);
  }
  // Lists in scrambled order: rebuild must not depend on it.
  std::vector<std::shared_ptr<KeyFrame>> kf_list = {kfs[4], kfs[1], kfs[5], kfs[0], kfs[3], kfs[2]};
  std::vector<std::shared_ptr<MapPoint>> mp_list(mps.rbegin(), mps.rend());
  map.rebuild(kf_list, mp_list);

  const Snapshot after = snapshot(map);
  EXPECT_EQ(after.weights, before.weights);
  EXPECT_EQ(after.observations, before.observations);
  EXPECT_EQ(after.parents, before.parents);
  EXPECT_EQ(after.children, before.children);
  EXPECT_EQ(map.num_keyframes(), 6u);
  EXPECT_EQ(map.num_map_points(), 300u);
}

TEST(Map, RebuildDropsLinksToAbsentPoints) {
  Map map;
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<std::shared_ptr<MapPoint>> mps;
  build_six(map, kfs, mps);
  // A Local-Map holding only the last three keyframes and the points below id 200.
  std::vector<std::shared_ptr<MapPoint>> some(mps.begin(), mps.begin() + 200);
  map.rebuild({kfs[3], kfs[4], kfs[5]}, some);
  EXPECT_EQ(kfs[5]->map_point_id(0), kNoId);     // point 200 is gone
  EXPECT_EQ(kfs[3]->map_point_id(0), 120u);
  EXPECT_EQ(kfs[3]->parent_id(), kNoId);         // parent 2 is not in the map
  EXPECT_EQ(kfs[4]->parent_id(), 3u);
  EXPECT_EQ(kfs[3]->weight(2), 0);
  EXPECT_EQ(kfs[3]->weight(4), 40);              // 160..199 remain shared
  EXPECT_EQ(kfs[4]->weight(5), 0);               // shared points 200..259 are absent
  EXPECT_EQ(mps[130]->observations().count(2), 0u);
}

namespace edge_slam {
// Scale prediction stays within the pyramid for any range, including the degenerate ones a
// corrupt record can carry (found by fuzz_map_update_message: -inf reached an int conversion).
TEST(ScalePyramid, PredictedLevelIsAlwaysAValidLevel) {
  const ScalePyramid p = ScalePyramid::make(8, 1.2f);
  EXPECT_EQ(p.predict_level(3.0, 3.0), 0);
  EXPECT_EQ(p.predict_level(3.0, 3.0 / 1.2 / 1.2), 2);
  EXPECT_EQ(p.predict_level(1e9, 1.0), 7) << "clamped to the coarsest level";
  for (double max_d : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    for (double d : {0.0, -2.0, 1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
      const int level = p.predict_level(max_d, d);
      EXPECT_GE(level, 0) << max_d << " / " << d;
      EXPECT_LT(level, 8) << max_d << " / " << d;
    }
}
}  // namespace edge_slam
