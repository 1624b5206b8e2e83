#include <gtest/gtest.h>

#include <unordered_map>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/module/relocalizer.h"
#include "synthetic_map.h"

using namespace edge_slam;
using namespace edge_slam_test;

namespace {

World room() {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> x(-3.0, 3.0), y(-1.5, 1.5), z(-0.4, 0.4);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 1500; ++i) pts.emplace_back(x(rng), y(rng), 3.5 + z(rng));
  return World(pts, 31);
}

// A non-empty vocabulary; its words are never used because every BoW here is preset.
std::shared_ptr<const BowVocabulary> tiny_vocabulary(const World& w) {
  auto v = std::make_shared<BowVocabulary>();
  VocabularyParams p;
  p.branching = 2;
  p.levels = 1;
  v->train({w.descriptors}, p);
  return v;
}

}  // namespace

TEST(Relocalizer, RecoversThePoseFromTheKeyFrameDatabase) {
  auto map = std::make_shared<Map>();
  auto db = std::make_shared<KeyFrameDatabase>();
  const World w = room();
  std::unordered_map<size_t, std::shared_ptr<MapPoint>> by_physical;
  for (int k = 0; k < 6; ++k) {
    View v;
    const auto T = look_from({0.4 * k - 1.0, 0, 0}, 0.05 * (k - 3));
    const auto kf = make_keyframe(*map, w, T, T, true, v);
    for (size_t i = 0; i < v.physical.size(); ++i) {
      const size_t p = v.physical[i];
      const auto it = by_physical.find(p);
      if (it == by_physical.end())
        by_physical[p] = make_point(*map, kf, i, w.points[p]);
      else
        add_observation(kf, i, it->second);
    }
    kf->update_connections(*map);
    db->add(kf);
  }
  for (const auto& [p, mp] : by_physical) mp->update_normal_and_depth(*map);

  // A lost frame between keyframes 2 and 3, with a small roll no keyframe has.
  Eigen::Isometry3d T_true = look_from({-0.1, 0.05, 0.1}, 0.02);
  T_true.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()).toRotationMatrix() * T_true.linear();
  View v;
  Frame frame(100, 10.0, render(w, T_true, true, v));
  KeyFrame bow_holder(999, 0, 0, frame.features, Eigen::Isometry3d::Identity());
  set_fake_bow(bow_holder, v);
  frame.set_bow(bow_holder.bow(), bow_holder.feature_vector());
  frame.map_points.assign(frame.size(), nullptr);
  frame.outliers.assign(frame.size(), false);

  BowPnpRelocalizer relocalizer(map, db, tiny_vocabulary(w));
  ASSERT_TRUE(relocalizer.relocalize(frame));
  const Eigen::Isometry3d err = frame.T_cw() * T_true.inverse();
  EXPECT_LT(err.translation().norm(), 0.005);
  EXPECT_LT(Eigen::AngleAxisd(err.linear()).angle(), 0.002);
  ASSERT_NE(frame.reference_kf, nullptr);
  EXPECT_GE(frame.num_matched(), 50);
}

TEST(Relocalizer, FailsCleanlyOnAnUnknownPlace) {
  auto map = std::make_shared<Map>();
  auto db = std::make_shared<KeyFrameDatabase>();
  const World w = room();
  View v0;
  const auto T = look_from({0, 0, 0}, 0);
  const auto kf = make_keyframe(*map, w, T, T, true, v0);
  for (size_t i = 0; i < v0.physical.size(); ++i) make_point(*map, kf, i, w.points[v0.physical[i]]);
  db->add(kf);
  const World elsewhere(std::vector<Eigen::Vector3d>(w.points), 77);  // same geometry, other descriptors
  View v;
  Frame frame(1, 0.0, render(elsewhere, T, true, v));
  KeyFrame bow_holder(999, 0, 0, frame.features, Eigen::Isometry3d::Identity());
  BowVector bow;
  FeatureVector fv;
  for (size_t i = 0; i < v.physical.size(); ++i) {
    bow[static_cast<WordId>(100000 + v.physical[i])] += 1.0 / v.physical.size();  // words nobody has
    fv[static_cast<NodeId>(100000 + v.physical[i])].push_back(static_cast<uint32_t>(i));
  }
  frame.set_bow(bow, fv);
  frame.map_points.assign(frame.size(), nullptr);
  frame.outliers.assign(frame.size(), false);
  BowPnpRelocalizer relocalizer(map, db, tiny_vocabulary(w));
  EXPECT_FALSE(relocalizer.relocalize(frame));
  EXPECT_EQ(frame.num_matched(), 0);
}
