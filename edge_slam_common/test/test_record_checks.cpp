// Every structural rule of io/record_checks.h rejects its violation with a reason, and the
// map builders (keyframe_from_record, rebuild_from_update) refuse such records before
// touching a map.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "edge_slam/io/map_records.h"
#include "edge_slam/io/record_checks.h"
#include "support/record_map.h"

namespace edge_slam {
namespace {

using test_support::SyntheticMap;

const SyntheticMap& fixture() {
  static const SyntheticMap m;
  return m;
}

// A valid KeyFrame record with observations, two new points and links.
KeyFrameRecord good_keyframe() {
  const SyntheticMap& m = fixture();
  KeyFrameRecord r = to_record(*m.map.keyframe(2), m.map, {1000 + 120 + 118, 1000 + 120 + 119});
  return r;
}

void expect_rejected(const std::function<void(KeyFrameRecord&)>& spoil, const char* rule, const char* word) {
  KeyFrameRecord r = good_keyframe();
  spoil(r);
  const std::string problem = keyframe_record_problem(r);
  EXPECT_FALSE(problem.empty()) << rule;
  EXPECT_NE(problem.find(word), std::string::npos) << rule << ": " << problem;
  const SyntheticMap& m = fixture();
  EXPECT_THROW(keyframe_from_record(r, m.camera, m.pyramid), std::invalid_argument) << rule;
}

TEST(RecordChecks, GoodRecordsPass) {
  const KeyFrameRecord r = good_keyframe();
  ASSERT_EQ(r.new_points.size(), 2u);
  EXPECT_EQ(keyframe_record_problem(r), "");
  EXPECT_EQ(map_update_record_problem(fixture().update()), "");
}

TEST(RecordChecks, KeyFrameFieldsAreEachChecked) {
  expect_rejected([](KeyFrameRecord& r) { r.id = kNoId; }, "reserved id", "reserved");
  expect_rejected([](KeyFrameRecord& r) { r.stamp = NAN; }, "stamp", "stamp");
  expect_rejected([](KeyFrameRecord& r) { r.created_wall = INFINITY; }, "created_wall", "created_wall");
  expect_rejected([](KeyFrameRecord& r) { r.T_wc.translation().x() = INFINITY; }, "pose", "pose");
  expect_rejected([](KeyFrameRecord& r) { r.T_wc.translation().y() = 1e9; }, "far pose", "range");
  expect_rejected([](KeyFrameRecord& r) { r.T_wc.linear() *= 2.0; }, "scaled rotation", "rotation");
  expect_rejected([](KeyFrameRecord& r) { r.T_wc.linear().col(0) *= -1.0; }, "reflection", "rotation");
  expect_rejected([](KeyFrameRecord& r) { r.features.depth.pop_back(); }, "depth size", "depth");
  expect_rejected([](KeyFrameRecord& r) { r.features.depth[3] = NAN; }, "NaN depth", "depth");
  expect_rejected([](KeyFrameRecord& r) { r.features.keypoints[1].pt.x = NAN; }, "NaN keypoint", "keypoint");
  expect_rejected([](KeyFrameRecord& r) { r.features.keypoints[1].pt.y = 1e30f; }, "far keypoint", "keypoint");
  expect_rejected([](KeyFrameRecord& r) { r.features.keypoints[1].angle = INFINITY; }, "angle", "angle");
  expect_rejected([](KeyFrameRecord& r) { r.features.keypoints[1].octave = -1; }, "octave", "octave");
  expect_rejected([](KeyFrameRecord& r) { r.features.descriptors = r.features.descriptors.colRange(0, 31).clone(); },
                  "descriptor length 31", "descriptors");
  expect_rejected([](KeyFrameRecord& r) { r.features.descriptors.convertTo(r.features.descriptors, CV_16U); },
                  "descriptor type", "descriptors");
  expect_rejected([](KeyFrameRecord& r) { r.observations[0].first = 100000; }, "observation index", "keypoint index");
  expect_rejected([](KeyFrameRecord& r) { r.observations[0].second = kNoId; }, "observation point id", "reserved");
  expect_rejected([](KeyFrameRecord& r) { r.observations[1].first = r.observations[0].first; }, "keypoint reused",
                  "reuses keypoint");
  expect_rejected([](KeyFrameRecord& r) { r.observations[1].second = r.observations[0].second; }, "point repeated",
                  "repeats point");
  expect_rejected([](KeyFrameRecord& r) { r.new_points[0].id = r.observations[0].second; },
                  "new point repeats an observation", "repeats point");
  expect_rejected([](KeyFrameRecord& r) { r.new_points[0].kp_index = r.observations[0].first; },
                  "new point on an observed keypoint", "reuses keypoint");
  expect_rejected([](KeyFrameRecord& r) { r.new_points[0].id = kNoId; }, "new point id", "reserved");
  expect_rejected([](KeyFrameRecord& r) { r.new_points[1].position.z() = NAN; }, "new point position", "position");
  expect_rejected([](KeyFrameRecord& r) { r.parent_id = r.id; }, "self parent", "own spanning-tree parent");
  expect_rejected([](KeyFrameRecord& r) { r.covisibility.push_back({r.id, 30}); }, "self link", "itself");
  expect_rejected([](KeyFrameRecord& r) { r.covisibility.push_back(r.covisibility.front()); }, "repeated link",
                  "repeated covisibility");
}

TEST(RecordChecks, MapPointFieldsAreEachChecked) {
  const MapPointRecord good = fixture().update().points.front();
  ASSERT_EQ(map_point_record_problem(good), "");
  auto rejected = [&](const std::function<void(MapPointRecord&)>& spoil) {
    MapPointRecord p = good;
    spoil(p);
    const bool bad = !map_point_record_problem(p).empty();
    if (bad) EXPECT_THROW(map_point_from_record(p), std::invalid_argument);
    return bad;
  };
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.id = kNoId; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.position.x() = NAN; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.position.y() = 3e38f; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.normal = {0, 0, 7}; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.normal.x() = NAN; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.min_distance = 3, p.max_distance = 2; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.min_distance = -1; }));
  EXPECT_TRUE(rejected([](MapPointRecord& p) { p.max_distance = INFINITY; }));
}

TEST(RecordChecks, UpdatesWithRepeatedIdsOrTreeCyclesLeaveTheMapUntouched) {
  const SyntheticMap& m = fixture();
  Map target;
  rebuild_from_update(target, m.update(), m.camera, m.pyramid, nullptr);
  ASSERT_EQ(target.num_keyframes(), 6u);
  auto refused = [&](const std::function<void(MapUpdateRecord&)>& spoil, const char* word) {
    MapUpdateRecord u = m.update();
    spoil(u);
    const std::string problem = map_update_record_problem(u);
    EXPECT_NE(problem.find(word), std::string::npos) << problem;
    EXPECT_THROW(rebuild_from_update(target, u, m.camera, m.pyramid, nullptr), std::invalid_argument);
    EXPECT_EQ(target.num_keyframes(), 6u);
    EXPECT_EQ(target.num_map_points(), 420u);
  };
  refused([](MapUpdateRecord& u) { u.keyframes[4].id = u.keyframes[1].id; }, "repeats");
  refused([](MapUpdateRecord& u) { u.points[9].id = u.points[2].id; }, "repeats");
  refused([](MapUpdateRecord& u) { u.points[5].position.z() = NAN; }, "points[5]");
  refused([](MapUpdateRecord& u) { u.keyframes[3].features.keypoints.pop_back(); }, "keyframes[3]");
  refused(
      [](MapUpdateRecord& u) {  // 0 -> 1 -> 2 -> 0
        u.keyframes[0].parent_id = 2;
        u.keyframes[1].parent_id = 0;
        u.keyframes[2].parent_id = 1;
      },
      "cycle");
}

TEST(RecordChecks, FeatureRecordsFromFramesAreChecked) {
  const SyntheticMap& m = fixture();
  FeatureRecord f = to_feature_record(m.map.keyframe(0)->features());
  EXPECT_EQ(feature_record_problem(f), "");
  f.keypoints.pop_back();
  EXPECT_NE(feature_record_problem(f), "");
  EXPECT_THROW(features_from_record(f, to_camera_record(m.camera), m.camera, m.pyramid), std::invalid_argument);
}

}  // namespace
}  // namespace edge_slam
