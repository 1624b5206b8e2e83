#include <gtest/gtest.h>

#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map_edit.h"
#include "edge_slam/module/keyframe_culling.h"
#include "edge_slam/module/local_mapping.h"
#include "edge_slam/module/map_point_culling.h"
#include "edge_slam/module/triangulation.h"
#include "edge_slam/util/robot_ids.h"
#include "synthetic_map.h"

using namespace edge_slam;
using namespace edge_slam_test;

namespace {

// Points on a wall 3 m in front of the origin.
World wall(int n, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-2.0, 2.0), y(-1.5, 1.5), z(-0.3, 0.3);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(x(rng), y(rng), 3.0 + z(rng));
  return World(pts, seed);
}

Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T, double rot, double trans, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Isometry3d d = Eigen::Isometry3d::Identity();
  d.linear() = Eigen::AngleAxisd(rot * n(rng), Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()).toRotationMatrix();
  d.translation() = trans * Eigen::Vector3d(n(rng), n(rng), n(rng));
  return d * T;
}

// One KeyFrame with depth per view, 5 cm apart along the wall, consecutive ids.
std::vector<std::shared_ptr<KeyFrame>> keyframes_along_wall(Map& map, const World& w, std::vector<View>& views) {
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  for (size_t k = 0; k < views.size(); ++k) {
    const auto T = look_from({0.05 * static_cast<double>(k), 0, 0}, 0);
    kfs.push_back(make_keyframe(map, w, T, T, true, views[k]));
  }
  return kfs;
}

}  // namespace

TEST(MapEdit, ReplaceMovesObservationsAndMarksTheOldPointBad) {
  Map map;
  const World w = wall(40);
  View v0, v1;
  const auto kf0 = make_keyframe(map, w, look_from({0, 0, 0}, 0), look_from({0, 0, 0}, 0), true, v0);
  const auto kf1 = make_keyframe(map, w, look_from({0.2, 0, 0}, 0), look_from({0.2, 0, 0}, 0), true, v1);
  const auto a = make_point(map, kf0, 0, w.points[v0.physical[0]]);
  const auto b = make_point(map, kf1, 0, w.points[v1.physical[0]]);
  add_observation(kf1, 1, a);  // kf1 sees both a (keypoint 1) and b (keypoint 0)
  a->increase_found(4);
  replace_map_point(map, a, b);
  EXPECT_TRUE(a->is_bad());
  EXPECT_EQ(a->replaced_by(), b->id());
  EXPECT_EQ(map.map_point(a->id()), nullptr);
  EXPECT_EQ(kf0->map_point_id(0), b->id());
  EXPECT_EQ(b->index_in(kf0->id()), 0);
  EXPECT_EQ(b->index_in(kf1->id()), 0);  // kf1 keeps its own link to b ...
  EXPECT_EQ(kf1->map_point_id(1), kNoId);  // ... and loses the duplicate one
  EXPECT_EQ(b->num_observations(), 2);
  EXPECT_EQ(b->found(), 1 + 5);
}

TEST(Triangulation, CreatesCorrectPointsFromTwoKeyFrames) {
  Map map;
  const World w = wall(300);
  View v0, v1;
  const Eigen::Isometry3d T0 = look_from({0, 0, 0}, 0), T1 = look_from({0.4, 0.05, 0}, -0.05);
  const auto kf0 = make_keyframe(map, w, T0, T0, false, v0);
  // The second keyframe has depth on every other keypoint: both creation paths are used.
  const auto kf1 = make_keyframe(map, w, T1, T1, true, v1);
  // 30 shared points make the two covisible; the rest are unmatched keypoints.
  std::unordered_map<size_t, size_t> index1;
  for (size_t i = 0; i < v1.physical.size(); ++i) index1[v1.physical[i]] = i;
  int shared = 0;
  for (size_t i = 0; i < v0.physical.size() && shared < 30; ++i) {
    const auto it = index1.find(v0.physical[i]);
    if (it == index1.end()) continue;
    const auto mp = make_point(map, kf0, i, w.points[v0.physical[i]]);
    add_observation(kf1, it->second, mp);
    ++shared;
  }
  kf0->update_connections(map);
  kf1->update_connections(map);
  ASSERT_EQ(kf1->weight(kf0->id()), 30);

  const auto created = triangulate_new_points(map, kf1);
  EXPECT_GT(created.size(), 150u);
  for (const auto& mp : created) {
    const int i = mp->index_in(kf1->id());
    ASSERT_GE(i, 0);
    EXPECT_LT((mp->position() - w.points[v1.physical[i]]).norm(), 1e-4);  // float keypoints
    EXPECT_EQ(mp->num_observations(), 2);
    EXPECT_GT(mp->max_distance(), 0.f);
  }
}

TEST(Triangulation, RejectsAPairThatDoesNotReproject) {
  Map map;
  const World w = wall(100);
  View v0, v1;
  const Eigen::Isometry3d T0 = look_from({0, 0, 0}, 0), T1 = look_from({0.4, 0, 0}, 0);
  const auto kf0 = make_keyframe(map, w, T0, T0, false, v0);
  const auto kf1 = make_keyframe(map, w, T1, T1, false, v1);
  Eigen::Vector3d x;
  // Keypoints of two different physical points do not intersect consistently.
  size_t j = 0;
  while (v1.physical[j] == v0.physical[0]) ++j;
  EXPECT_FALSE(triangulate_pair(*kf0, 0, *kf1, j, x) &&
               (x - w.points[v0.physical[0]]).norm() < 1e-3);
}

TEST(MapPointCulling, LowFoundRatioAndTooFewObserversAreErased) {
  Map map;
  const World w = wall(60);
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<View> views(4);
  for (int k = 0; k < 4; ++k) {  // no depth: every observation counts once
    const auto T = look_from({0.1 * k, 0, 0}, 0);
    kfs.push_back(make_keyframe(map, w, T, T, false, views[k]));
  }
  size_t next_keypoint = 0;  // the four views are identical up to a small shift: same order
  auto point_seen_by = [&](int n) {
    const size_t i = next_keypoint++;
    const auto mp = make_point(map, kfs[0], i, w.points[views[0].physical[i]]);
    for (int k = 1; k < n; ++k) add_observation(kfs[k], i, mp);
    return mp;
  };
  RecentMapPoints recent;
  const auto rarely_found = point_seen_by(4);
  rarely_found->increase_visible(10);  // found 1 of 11
  const auto two_observers = point_seen_by(2);
  const auto three_observers = point_seen_by(3);
  for (const auto& mp : {rarely_found, two_observers, three_observers}) recent.add(mp->id(), kfs[0]->id());

  EXPECT_EQ(recent.cull(map, kfs[1]->id()), 1);  // only the found ratio applies this early
  EXPECT_TRUE(rarely_found->is_bad());
  EXPECT_EQ(map.map_point(rarely_found->id()), nullptr);
  EXPECT_EQ(kfs[0]->map_point_id(0), kNoId);
  EXPECT_EQ(recent.cull(map, kfs[2]->id()), 1);  // two keyframes later: < 3 observers goes
  EXPECT_TRUE(two_observers->is_bad());
  EXPECT_FALSE(three_observers->is_bad());
  EXPECT_EQ(recent.size(), 1u);
  EXPECT_EQ(recent.cull(map, kfs[3]->id()), 0);  // three keyframes later it leaves probation
  EXPECT_EQ(recent.size(), 0u);
  EXPECT_FALSE(three_observers->is_bad());
}

TEST(MapPointCulling, AnObservationWithDepthCountsTwice) {
  Map map;
  const World w = wall(60);
  View v0, v1, v2;
  const auto T = look_from({0, 0, 0}, 0);
  const auto kf0 = make_keyframe(map, w, T, T, true, v0);
  make_keyframe(map, w, T, T, true, v1);
  const auto kf2 = make_keyframe(map, w, T, T, true, v2);
  std::vector<size_t> stereo;  // keypoints whose virtual right coordinate is in the image
  for (size_t i = 0; i < v0.physical.size() && stereo.size() < 2; ++i)
    if (kf0->features().right_x[i] >= 0) stereo.push_back(i);
  ASSERT_EQ(stereo.size(), 2u);
  const auto alone = make_point(map, kf0, stereo[0], w.points[v0.physical[stereo[0]]]);  // weight 2
  const auto pair = make_point(map, kf0, stereo[1], w.points[v0.physical[stereo[1]]]);
  add_observation(map.keyframe(1), stereo[1], pair);  // same view: weight 4
  EXPECT_EQ(pair->weighted_observations(map), 4);
  // The capped count KeyFrame condition 4 uses: the same figure up to the cap, never above it.
  for (int cap : {0, 1, 2, 3, 4, 5, 16, 17}) EXPECT_EQ(pair->weighted_observations_capped(map, cap), std::min(cap, 4)) << cap;
  for (int cap : {1, 2, 3}) EXPECT_EQ(alone->weighted_observations_capped(map, cap), std::min(cap, 2)) << cap;
  RecentMapPoints recent;
  recent.add(alone->id(), kf0->id());
  recent.add(pair->id(), kf0->id());
  EXPECT_EQ(recent.cull(map, kf2->id()), 1);
  EXPECT_TRUE(alone->is_bad());
  EXPECT_FALSE(pair->is_bad());
}

// The edge installs a mobile's new points as its KeyFrame record brings them: in the map, named
// by the KeyFrame, made by it, but without the observation tracking adds in a monolithic run.
// Local-Mapping must put them on probation all the same: none was ever culled on the edge (0 of
// ~10^5 in a 6-minute run against 130,000 culled in the monolithic run of the same sequence).
TEST(MapPointCulling, PointsAKeyFrameRecordBroughtAreOnProbationLikeTrackingMadeOnes) {
  auto map = std::make_shared<Map>();
  const World w = wall(120);
  View v1;
  const auto T = look_from({0, 0, 0}, 0);
  const auto kf1 = make_keyframe(*map, w, T, T, true, v1);
  std::vector<std::shared_ptr<MapPoint>> tracked_made, record_made;
  for (size_t i = 0; i < v1.physical.size(); ++i) {
    if (kf1->features().right_x[i] < 0) continue;  // depth: one keyframe weighs 2 < 3 observers
    if (i % 2 == 0) {
      tracked_made.push_back(make_point(*map, kf1, i, w.points[v1.physical[i]]));
    } else {
      auto mp = std::make_shared<MapPoint>(map->new_map_point_id(), w.points[v1.physical[i]], kf1->id());
      mp->set_descriptor(kf1->features().descriptor(i));
      map->add_map_point(mp);
      kf1->set_map_point_id(i, mp->id());  // named by the KeyFrame, no observation yet
      record_made.push_back(mp);
    }
  }
  ASSERT_GT(record_made.size(), 10u);
  ASSERT_GT(tracked_made.size(), 10u);
  // Two later KeyFrames elsewhere (another wall, not covisible): nobody observes the points again.
  const World other = wall(60, 17);
  View v2, v3;
  const auto kf2 = make_keyframe(*map, other, look_from({5, 0, 0}, 0), look_from({5, 0, 0}, 0), true, v2);
  const auto kf3 = make_keyframe(*map, other, look_from({5.1, 0, 0}, 0), look_from({5.1, 0, 0}, 0), true, v3);
  LocalMappingParams params;
  params.local_ba = false;
  params.cull_keyframes = false;
  LocalMapping mapping(map, std::make_shared<KeyFrameDatabase>(), nullptr, params);
  for (const auto& kf : {kf1, kf2, kf3}) mapping.process_keyframe(kf);

  size_t record_culled = 0, tracked_culled = 0;
  for (const auto& mp : record_made) record_culled += mp->is_bad() ? 1 : 0;
  for (const auto& mp : tracked_made) tracked_culled += mp->is_bad() ? 1 : 0;
  EXPECT_EQ(tracked_culled, tracked_made.size());
  EXPECT_EQ(record_culled, record_made.size()) << "points a record brought must be culled like tracking's";
  EXPECT_GE(mapping.stats().points_culled, static_cast<int>(record_made.size() + tracked_made.size()));
}

// The found-ratio test split between the two sides: the mobile judges (its tracking has the
// counts) and names the failures; the edge culls the named points that are on probation there.
TEST(MapPointCulling, TheMobileRefutesRecentPointsTrackingRarelyFound) {
  Map map;
  const World w = wall(60);
  std::vector<View> views(6);
  const std::vector<std::shared_ptr<KeyFrame>> kfs = keyframes_along_wall(map, w, views);
  auto point_of = [&](int kf, size_t i) { return make_point(map, kfs[kf], i, w.points[views[kf].physical[i]]); };
  const auto recent_rarely_found = point_of(3, 0);
  recent_rarely_found->increase_visible(10);  // found 1 of 11 frames predicting it
  const auto recent_often_found = point_of(3, 1);
  recent_often_found->increase_visible(10);
  recent_often_found->increase_found(9);       // 10 of 11
  const auto old_rarely_found = point_of(0, 2);  // 5 KeyFrames old: past probation
  old_rarely_found->increase_visible(10);
  const auto own_new_point = point_of(5, 3);   // made by the KeyFrame being recorded
  own_new_point->increase_visible(10);

  MapPointCullingParams params;  // ratio 0.25, probation 3 KeyFrames
  const std::vector<uint32_t> refuted = refute_unfound_points(map, kfs[5]->id(), params);
  ASSERT_EQ(refuted, std::vector<uint32_t>{recent_rarely_found->id()});
  EXPECT_TRUE(recent_rarely_found->is_bad());
  EXPECT_EQ(map.map_point(recent_rarely_found->id()), nullptr);
  EXPECT_EQ(kfs[3]->map_point_id(0), kNoId);
  for (const auto& kept : {recent_often_found, old_rarely_found, own_new_point}) EXPECT_FALSE(kept->is_bad());
}

TEST(MapPointCulling, TheEdgeCullsRefutedPointsOnlyWhileOnProbation) {
  Map map;
  const World w = wall(60);
  std::vector<View> views(6);
  const std::vector<std::shared_ptr<KeyFrame>> kfs = keyframes_along_wall(map, w, views);
  auto seen_by_three = [&](int kf, size_t i) {  // weight 6: the observer rule keeps it
    const auto mp = make_point(map, kfs[kf], i, w.points[views[kf].physical[i]]);
    for (int k = kf + 1; k < kf + 3; ++k) add_observation(kfs[k], i, mp);
    return mp;
  };
  const auto refuted_recent = seen_by_three(2, 0);
  const auto unrefuted_recent = seen_by_three(2, 1);
  RecentMapPoints recent;
  recent.add(refuted_recent->id(), kfs[2]->id());
  recent.add(unrefuted_recent->id(), kfs[2]->id());
  // The edge's own counts say nothing (1 of 1): only the mobile's word culls.
  const std::unordered_set<uint32_t> refuted{refuted_recent->id(), 999999u};  // one unknown id
  int num_refuted = 0;
  EXPECT_EQ(recent.cull(map, kfs[3]->id(), &refuted, &num_refuted), 1);
  EXPECT_EQ(num_refuted, 1);
  EXPECT_TRUE(refuted_recent->is_bad());
  EXPECT_FALSE(unrefuted_recent->is_bad());

  // Past probation the point has left the list: a late refutation changes nothing.
  EXPECT_EQ(recent.cull(map, kfs[5]->id()), 0);
  const std::unordered_set<uint32_t> late{unrefuted_recent->id()};
  EXPECT_EQ(recent.cull(map, kfs[5]->id(), &late, &num_refuted), 0);
  EXPECT_FALSE(unrefuted_recent->is_bad());
  EXPECT_FALSE(on_probation(kfs[2]->id(), kfs[2]->id(), MapPointCullingParams{}));
  EXPECT_TRUE(on_probation(kfs[2]->id(), kfs[5]->id(), MapPointCullingParams{}));
  EXPECT_FALSE(on_probation(kfs[1]->id(), kfs[5]->id(), MapPointCullingParams{}));
  EXPECT_FALSE(on_probation(kfs[2]->id(), keyframe_id_space(1).first + 3, MapPointCullingParams{}));  // another robot's
}

TEST(KeyFrameCulling, RedundantKeyFrameIsCulledAndItsChildrenReattached) {
  Map map;
  KeyFrameDatabase db;
  const World w = wall(200);
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<View> views(5);
  for (int k = 0; k < 5; ++k) {
    const auto T = look_from({0.02 * k, 0, 0}, 0);  // nearly the same view: all see all
    kfs.push_back(make_keyframe(map, w, T, T, true, views[k]));
  }
  // Every keyframe observes every physical point through one shared map point.
  std::unordered_map<size_t, std::shared_ptr<MapPoint>> by_physical;
  for (int k = 0; k < 5; ++k)
    for (size_t i = 0; i < views[k].physical.size(); ++i) {
      const size_t p = views[k].physical[i];
      auto it = by_physical.find(p);
      if (it == by_physical.end())
        by_physical[p] = make_point(map, kfs[k], i, w.points[p]);
      else
        add_observation(kfs[k], i, it->second);
    }
  for (const auto& kf : kfs) {
    kf->update_connections(map);
    db.add(kf);
  }
  // A sixth keyframe with its own points is not redundant.
  const World other = wall(120, 99);
  View v5;
  const auto T5 = look_from({0, 0, 0}, 0);  // renders only the other world's points
  const auto lonely = make_keyframe(map, other, T5, T5, true, v5);
  for (size_t i = 0; i < v5.physical.size(); ++i) make_point(map, lonely, i, other.points[v5.physical[i]]);
  add_observation(lonely, 0, by_physical.begin()->second);
  lonely->update_connections(map);
  ASSERT_NE(lonely->parent_id(), kNoId);
  db.add(lonely);
  EXPECT_FALSE(is_redundant_keyframe(map, *lonely));
  EXPECT_TRUE(is_redundant_keyframe(map, *kfs[1]));

  const int culled = cull_redundant_keyframes(map, &db, *kfs[4]);
  EXPECT_GE(culled, 1);
  EXPECT_FALSE(kfs[0]->is_bad());  // the root stays
  EXPECT_FALSE(lonely->is_bad());
  // Consistency: every remaining keyframe has a good parent (or is the root), and culled
  // ones are gone from map, database and observations.
  for (const auto& kf : map.keyframes()) {
    if (kf->id() == kfs[0]->id()) continue;
    const auto parent = map.keyframe(kf->parent_id());
    ASSERT_NE(parent, nullptr) << "keyframe " << kf->id() << " parent " << kf->parent_id();
    EXPECT_TRUE(parent->children().count(kf->id()));
  }
  for (const auto& kf : kfs) {
    if (!kf->is_bad()) continue;
    EXPECT_EQ(map.keyframe(kf->id()), nullptr);
    for (const auto& mp : map.map_points()) EXPECT_LT(mp->index_in(kf->id()), 0);
  }
  EXPECT_EQ(db.size(), map.num_keyframes());
}

TEST(LocalMapping, LocalBundleAdjustmentReducesErrorAndKeepsFixedKeyFramesFixed) {
  auto map = std::make_shared<Map>();
  const World w = wall(250);
  std::mt19937 rng(5);
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<View> views(5);
  std::unordered_map<size_t, std::shared_ptr<MapPoint>> by_physical;
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int k = 0; k < 5; ++k) {
    const auto T = look_from({0.15 * k, 0, 0}, 0.02 * k);
    const auto estimate = k == 0 ? T : perturbed(T, 0.003, 0.01, rng);
    kfs.push_back(make_keyframe(*map, w, T, estimate, true, views[k]));
    for (size_t i = 0; i < views[k].physical.size(); ++i) {
      const size_t p = views[k].physical[i];
      auto it = by_physical.find(p);
      if (it == by_physical.end())
        by_physical[p] = make_point(*map, kfs[k], i, w.points[p] + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
      else
        add_observation(kfs[k], i, it->second);
    }
    kfs[k]->update_connections(*map);
  }
  // A far keyframe seeing only 10 of the local points: outside the window, hence fixed.
  const World extra = wall(100, 11);
  View vf;
  const auto Tf = look_from({0, 0, -0.5}, 0);
  const auto far = make_keyframe(*map, extra, Tf, perturbed(Tf, 0.002, 0.01, rng), true, vf);
  for (size_t i = 0; i < vf.physical.size(); ++i) make_point(*map, far, i, extra.points[vf.physical[i]]);
  int linked = 0;
  for (size_t i = 0; i < views[4].physical.size() && linked < 10; ++i) {
    const auto mp = by_physical[views[4].physical[i]];
    const uint32_t slot = static_cast<uint32_t>(i);  // reuse an extra keypoint slot index
    if (slot < vf.physical.size() && far->map_point_id(slot) != kNoId) {
      erase_observation(*map, far, map->map_point(far->map_point_id(slot)));
      add_observation(far, slot, mp);
      ++linked;
    }
  }
  far->update_connections(*map);
  for (const auto& [p, mp] : by_physical) {
    mp->update_normal_and_depth(*map);
    mp->update_descriptor(*map);
  }
  ASSERT_EQ(kfs[4]->weight(far->id()), 0);

  const Eigen::Isometry3d far_before = far->T_cw(), root_before = kfs[0]->T_cw();
  const Eigen::Isometry3d k4_before = kfs[4]->T_cw();
  const double before = reprojection_error(*map);
  LocalMappingParams params;
  params.cull_keyframes = false;
  LocalMapping mapping(map, std::make_shared<KeyFrameDatabase>(), nullptr, params);
  mapping.process_keyframe(kfs[4]);
  const double after = reprojection_error(*map);
  EXPECT_LT(after, 0.05 * before) << "before " << before << " after " << after;
  EXPECT_EQ(mapping.stats().local_ba_runs, 1);
  EXPECT_TRUE(far->T_cw().isApprox(far_before, 0.0));
  EXPECT_TRUE(kfs[0]->T_cw().isApprox(root_before, 0.0));
  EXPECT_FALSE(kfs[4]->T_cw().isApprox(k4_before, 1e-12));
  EXPECT_EQ(mapping.local_ba_times_ms().size(), 1u);
}

TEST(LocalMapping, KeyFrameErasedWhileQueuedIsSkipped) {
  auto map = std::make_shared<Map>();
  auto db = std::make_shared<KeyFrameDatabase>();
  const World w = wall(150);
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<View> views(3);
  std::unordered_map<size_t, std::shared_ptr<MapPoint>> by_physical;
  for (int k = 0; k < 3; ++k) {
    const auto T = look_from({0.1 * k, 0, 0}, 0);
    kfs.push_back(make_keyframe(*map, w, T, T, true, views[k]));
    for (size_t i = 0; i < views[k].physical.size(); ++i) {
      const size_t p = views[k].physical[i];
      auto it = by_physical.find(p);
      if (it == by_physical.end())
        by_physical[p] = make_point(*map, kfs[k], i, w.points[p]);
      else
        add_observation(kfs[k], i, it->second);
    }
    kfs[k]->update_connections(*map);
  }
  LocalMapping mapping(map, db, nullptr);
  std::vector<bool> idle_reports;
  mapping.on_idle_changed = [&](bool idle) { idle_reports.push_back(idle); };
  int handed_on = 0;
  mapping.on_keyframe_processed = [&](const std::shared_ptr<KeyFrame>&) { ++handed_on; };
  {
    std::lock_guard<std::mutex> lock(map->update_mutex());
    ASSERT_TRUE(cull_keyframe(*map, db.get(), kfs[1]));  // erased before the mapper sees it
  }
  mapping.insert_keyframe(kfs[1]);
  mapping.insert_keyframe(nullptr);
  mapping.insert_keyframe(kfs[2]);
  EXPECT_FALSE(mapping.idle());
  mapping.start();
  ASSERT_TRUE(mapping.wait_until_idle(10.0));
  mapping.shutdown();
  EXPECT_EQ(mapping.stats().keyframes_skipped, 2);
  EXPECT_EQ(mapping.stats().keyframes_processed, 1);
  EXPECT_EQ(handed_on, 1);
  EXPECT_TRUE(mapping.idle());
  ASSERT_FALSE(idle_reports.empty());
  EXPECT_TRUE(idle_reports.back());
}

TEST(LocalMapping, StopAndReleasePauseTheThread) {
  auto map = std::make_shared<Map>();
  LocalMapping mapping(map, std::make_shared<KeyFrameDatabase>(), nullptr);
  mapping.start();
  mapping.request_stop();
  ASSERT_TRUE(mapping.wait_until_stopped(5.0));
  EXPECT_TRUE(mapping.stopped());
  mapping.release();
  for (int i = 0; i < 200 && mapping.stopped(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_FALSE(mapping.stopped());
  mapping.shutdown();
}

// Several robots (issue #16): a pause for one robot's map (its loop correction or merge) holds
// back that map's KeyFrames, in order, while another map's are mapped; pauses stack.
TEST(LocalMapping, APauseForOneMapHoldsItsKeyFramesBackAndMapsTheOthers) {
  auto map = std::make_shared<Map>();
  const World w = wall(150);
  std::vector<View> views(4);
  const auto kfs = keyframes_along_wall(*map, w, views);
  LocalMappingParams params;
  params.local_ba = false;
  LocalMapping mapping(map, std::make_shared<KeyFrameDatabase>(), nullptr, params);
  mapping.group_of = [&](uint32_t id) { return id >= kfs[2]->id() ? 1 : 0; };  // 0, 1: map 0; 2, 3: map 1
  std::mutex m;
  std::condition_variable cv;
  std::vector<uint32_t> done;
  mapping.on_keyframe_done = [&](const std::shared_ptr<KeyFrame>& kf) {
    std::lock_guard<std::mutex> lock(m);
    done.push_back(kf->id());
    cv.notify_all();
  };
  auto wait_for_count = [&](size_t n) {
    std::unique_lock<std::mutex> lock(m);
    return cv.wait_for(lock, std::chrono::seconds(10), [&] { return done.size() >= n; });
  };
  mapping.start();
  mapping.request_stop({0});
  mapping.request_stop({0});  // a second request (a full BA's) for the same map
  ASSERT_TRUE(mapping.wait_until_stopped(5.0));
  EXPECT_TRUE(mapping.stopped());
  mapping.insert_keyframe(kfs[0]);
  mapping.insert_keyframe(kfs[2]);
  ASSERT_TRUE(wait_for_count(1));
  mapping.release({0});  // one request is still in force
  mapping.insert_keyframe(kfs[1]);
  mapping.insert_keyframe(kfs[3]);
  ASSERT_TRUE(wait_for_count(2));
  {
    // The queue is first in, first out: kfs[0] and kfs[1] were taken before kfs[2] and kfs[3]
    // and held back.
    std::lock_guard<std::mutex> lock(m);
    EXPECT_EQ(done, (std::vector<uint32_t>{kfs[2]->id(), kfs[3]->id()}));
  }
  EXPECT_FALSE(mapping.idle());
  EXPECT_EQ(mapping.stats().keyframes_mapped_beside_a_pause, 2);
  mapping.release({0});
  ASSERT_TRUE(mapping.wait_until_idle(10.0));
  mapping.shutdown();
  std::lock_guard<std::mutex> lock(m);
  EXPECT_EQ(done, (std::vector<uint32_t>{kfs[2]->id(), kfs[3]->id(), kfs[0]->id(), kfs[1]->id()}));
  EXPECT_EQ(mapping.stats().keyframes_processed, 4);
}
