// Map objects -> wire records -> a rebuilt map: the Local-Map update path without ROS.
#include <gtest/gtest.h>

#include "edge_slam/io/map_records.h"
#include "support/record_map.h"

namespace edge_slam {
namespace {

using test_support::SyntheticMap;

TEST(MapRecords, RebuildFromUpdateReproducesTheMap) {
  SyntheticMap a;
  Map b;
  const RebuildStats stats = rebuild_from_update(b, a.update(), a.camera, a.pyramid, nullptr);
  EXPECT_EQ(stats.keyframes, 6u);
  EXPECT_EQ(stats.map_points, 420u);
  EXPECT_EQ(stats.dropped_observations, 0u);
  for (const auto& kf : a.map.keyframes()) {
    const auto rebuilt = b.keyframe(kf->id());
    ASSERT_TRUE(rebuilt);
    EXPECT_EQ(rebuilt->connection_weights(), kf->connection_weights()) << "KF " << kf->id();
    EXPECT_EQ(rebuilt->map_point_ids(), kf->map_point_ids());
    EXPECT_TRUE(rebuilt->T_cw().isApprox(kf->T_cw(), 1e-12));
    EXPECT_EQ(cv::norm(rebuilt->features().descriptors, kf->features().descriptors, cv::NORM_HAMMING), 0);
  }
  EXPECT_EQ(b.keyframe(2)->weight(3), 60);
  EXPECT_EQ(b.map_point(1000 + 130)->num_observations(), 2);
}

TEST(MapRecords, NewPointsTravelInFullAndComeBackWithTheirDescriptor) {
  SyntheticMap a;
  const auto kf = a.map.keyframe(5);
  std::unordered_set<uint32_t> created;
  for (uint32_t i = 60; i < 120; ++i) created.insert(1000 + 300 + i);
  const KeyFrameRecord r = to_record(*kf, a.map, created);
  EXPECT_EQ(r.new_points.size(), 60u);
  EXPECT_EQ(r.observations.size(), 60u);
  const auto received = keyframe_from_record(r, a.camera, a.pyramid);
  const auto mp = map_point_from_new_point(r.new_points[0], *received);
  EXPECT_EQ(mp->reference_kf_id(), 5u);
  const Descriptor d = mp->descriptor();
  EXPECT_EQ(descriptor_distance(d.data(), received->features().descriptor(r.new_points[0].kp_index)), 0);
}

TEST(MapRecords, CameraMismatchIsRejectedAndLeavesTheMapUntouched) {
  SyntheticMap a;
  MapUpdateRecord u = a.update();
  u.keyframes[3].camera.fx = 517.3;
  Map b;
  rebuild_from_update(b, a.update(), a.camera, a.pyramid, nullptr);
  EXPECT_THROW(rebuild_from_update(b, u, a.camera, a.pyramid, nullptr), std::invalid_argument);
  EXPECT_EQ(b.num_keyframes(), 6u);
  u = a.update();
  u.keyframes[1].features.keypoints[4].octave = 12;
  EXPECT_THROW(rebuild_from_update(b, u, a.camera, a.pyramid, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace edge_slam
