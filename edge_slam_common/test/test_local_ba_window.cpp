// The local BA window (module/map_ba_bridge.h): unbounded it is ORB-SLAM2's (the keyframe, all
// its covisible keyframes free, every other observer of their points fixed); bounded it keeps
// the strongest covisibles free and the observers with the most window observations fixed.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "edge_slam/data/map_edit.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "synthetic_map.h"

using namespace edge_slam;
using namespace edge_slam_test;

namespace {

// Eight keyframes 0.25 m apart along a wide wall, each point shared by every keyframe that
// sees it: covisibility falls with distance, so the window's choices are unambiguous.
struct Corridor {
  Map map;
  std::vector<std::shared_ptr<KeyFrame>> kfs;

  Corridor() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> x(-2.0, 4.0), y(-1.0, 1.0), z(-0.2, 0.2);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 600; ++i) pts.emplace_back(x(rng), y(rng), 2.5 + z(rng));
    const World w(pts, 7);
    std::vector<View> views(8);
    std::unordered_map<size_t, std::shared_ptr<MapPoint>> by_physical;
    for (int k = 0; k < 8; ++k) {
      const auto T = look_from({0.25 * k, 0, 0}, 0);
      kfs.push_back(make_keyframe(map, w, T, T, true, views[k]));
      for (size_t i = 0; i < views[k].physical.size(); ++i) {
        const size_t p = views[k].physical[i];
        const auto it = by_physical.find(p);
        if (it == by_physical.end())
          by_physical[p] = make_point(map, kfs[k], i, w.points[p]);
        else
          add_observation(kfs[k], i, it->second);
      }
    }
    for (const auto& kf : kfs) kf->update_connections(map);
  }
};

std::set<uint32_t> ids(const BundleAdjustmentProblem& p, bool fixed) {
  std::set<uint32_t> s;
  for (const auto& b : p.keyframes)
    if (b.fixed == fixed) s.insert(b.id);
  return s;
}

void expect_observations_name_problem_members(const BundleAdjustmentProblem& p) {
  std::set<uint32_t> kf_ids, point_ids;
  for (const auto& b : p.keyframes) kf_ids.insert(b.id);
  for (const auto& b : p.points) point_ids.insert(b.id);
  for (const auto& o : p.observations) {
    EXPECT_TRUE(kf_ids.count(o.keyframe_id)) << "observation by keyframe " << o.keyframe_id << " outside the window";
    EXPECT_TRUE(point_ids.count(o.point_id));
  }
}

}  // namespace

TEST(LocalBaWindow, UnboundedIsTheKeyFrameWithAllItsCovisiblesAndEveryObserverFixed) {
  Corridor c;
  const KeyFrame& kf = *c.kfs[7];
  const BundleAdjustmentProblem p = build_local_ba_problem(c.map, kf);
  std::set<uint32_t> expected_free{kf.id()};
  for (uint32_t id : kf.ordered_neighbours())
    if (c.map.keyframe(id)->parent_id() != kNoId) expected_free.insert(id);
  EXPECT_EQ(ids(p, false), expected_free);
  ASSERT_GE(expected_free.size(), 4u);
  // Every keyframe observing a window point is in the problem.
  std::set<uint32_t> observers;
  for (const auto& b : p.points) c.map.map_point(b.id)->for_each_observation([&](uint32_t id, int) { observers.insert(id); });
  std::set<uint32_t> all = ids(p, false), fixed = ids(p, true);
  all.insert(fixed.begin(), fixed.end());
  EXPECT_EQ(all, observers);
  expect_observations_name_problem_members(p);
}

TEST(LocalBaWindow, BoundedKeepsTheStrongestCovisiblesFreeAndTheBusiestObserversFixed) {
  Corridor c;
  const KeyFrame& kf = *c.kfs[7];
  const std::vector<uint32_t> neighbours = kf.ordered_neighbours();
  ASSERT_GE(neighbours.size(), 5u);
  LocalBaWindow window;
  window.max_free_keyframes = 3;
  window.max_fixed_keyframes = 2;
  const BundleAdjustmentProblem p = build_local_ba_problem(c.map, kf, window);

  // Free: the keyframe and its two strongest covisibles (none of them the root here).
  const std::set<uint32_t> free = ids(p, false), fixed = ids(p, true);
  EXPECT_EQ(free, (std::set<uint32_t>{kf.id(), neighbours[0], neighbours[1]}));
  // Fixed: the two other keyframes observing the most points of the window.
  std::set<uint32_t> window_points;
  for (const auto& b : p.points) window_points.insert(b.id);
  std::map<uint32_t, int> count;
  for (uint32_t id : window_points)
    c.map.map_point(id)->for_each_observation([&](uint32_t obs_kf, int) {
      if (!free.count(obs_kf)) ++count[obs_kf];
    });
  std::vector<std::pair<int, uint32_t>> ranked;
  for (const auto& [id, n] : count) ranked.emplace_back(-n, id);
  std::sort(ranked.begin(), ranked.end());
  ASSERT_GE(ranked.size(), 3u);
  EXPECT_EQ(fixed, (std::set<uint32_t>{ranked[0].second, ranked[1].second}));
  // The observations of keyframes left out are not in the problem; the rest are.
  expect_observations_name_problem_members(p);
  size_t expected_observations = 0;
  for (uint32_t id : window_points)
    c.map.map_point(id)->for_each_observation([&](uint32_t obs_kf, int) {
      if (free.count(obs_kf) || fixed.count(obs_kf)) ++expected_observations;
    });
  EXPECT_EQ(p.observations.size(), expected_observations);
  EXPECT_LT(p.observations.size(), build_local_ba_problem(c.map, kf).observations.size());
}
