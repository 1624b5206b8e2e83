#include <gtest/gtest.h>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

#include "support/blank_features.h"

using namespace edge_slam;

namespace {
std::shared_ptr<const FrameFeatures> features(size_t n) { return blank_features(n); }

// Adds a keyframe observing the given map point ids and updates its connections.
std::shared_ptr<KeyFrame> add_kf(Map& map, uint32_t id, const std::vector<uint32_t>& mp_ids) {
  auto kf = std::make_shared<KeyFrame>(id, id, 0.0, features(mp_ids.size()), Eigen::Isometry3d::Identity());
  map.add_keyframe(kf);
  for (size_t i = 0; i < mp_ids.size(); ++i) {
    auto mp = map.map_point(mp_ids[i]);
    if (!mp) {
      mp = std::make_shared<MapPoint>(mp_ids[i], Eigen::Vector3d(0, 0, 1), id);
      map.add_map_point(mp);
    }
    kf->set_map_point_id(i, mp_ids[i]);
    mp->add_observation(id, static_cast<int>(i));
  }
  kf->update_connections(map);
  return kf;
}

std::vector<uint32_t> range(uint32_t a, uint32_t b) {
  std::vector<uint32_t> v;
  for (uint32_t i = a; i < b; ++i) v.push_back(i);
  return v;
}
std::vector<uint32_t> concat(std::vector<uint32_t> a, const std::vector<uint32_t>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}
}  // namespace

TEST(Covisibility, WeightsAreSharedObservationsWithThreshold15) {
  Map map;
  auto a = add_kf(map, 0, range(0, 100));
  auto b = add_kf(map, 1, concat(range(0, 15), range(100, 150)));   // shares 15 with A
  auto c = add_kf(map, 2, concat(range(20, 34), range(200, 250)));  // shares 14 with A only
  auto d = add_kf(map, 3, concat(concat(range(40, 54), range(100, 114)), range(300, 340)));  // 14 + 14

  EXPECT_EQ(a->weight(1), 15);  // at the threshold: an edge, both ways
  EXPECT_EQ(b->weight(0), 15);
  EXPECT_EQ(b->parent_id(), 0u);
  // Below the threshold with nobody else: only the best keyframe is linked.
  EXPECT_EQ(c->connection_weights(), (std::map<uint32_t, int>{{0, 14}}));
  EXPECT_EQ(a->weight(2), 14);
  EXPECT_EQ(c->parent_id(), 0u);
  // Two sub-threshold neighbours with the same weight: one best edge (lowest id on ties).
  EXPECT_EQ(d->connection_weights().size(), 1u);
  EXPECT_EQ(d->weight(0), 14);
  EXPECT_EQ(b->weight(3), 0);
  EXPECT_EQ(a->ordered_neighbours(), std::vector<uint32_t>({1, 2, 3}));
  EXPECT_EQ(a->covisibles_with_weight(15), std::vector<uint32_t>({1}));
  EXPECT_EQ(a->best_covisibles(2), std::vector<uint32_t>({1, 2}));
  EXPECT_EQ(a->children(), std::set<uint32_t>({1, 2, 3}));
}

TEST(Covisibility, UpdateRefreshesWeightsWhenObservationsChange) {
  Map map;
  auto a = add_kf(map, 0, range(0, 100));
  auto b = add_kf(map, 1, range(0, 40));
  EXPECT_EQ(a->weight(1), 40);
  // B stops observing 20 of the points.
  for (uint32_t i = 0; i < 20; ++i) {
    map.map_point(i)->erase_observation(1);
    b->erase_map_point_id(i);
  }
  b->update_connections(map);
  EXPECT_EQ(b->weight(0), 20);
  EXPECT_EQ(a->weight(1), 20);
}
