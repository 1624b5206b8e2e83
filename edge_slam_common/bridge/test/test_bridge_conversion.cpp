// Round trips and rejection of malformed messages for the message <-> record bridge.
#include <edge_slam/io/keypoint_coding.h>
#include <edge_slam/io/new_point_position.h>
#include <edge_slam_bridge/message_conversion.h>
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "support/wire_fixtures.h"

namespace edge_slam {
namespace {

KeyFrameRecord make_keyframe(size_t n_features, size_t n_obs, size_t n_new, uint32_t seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(0.f, 639.f), uy(0.f, 479.f), ua(0.f, 359.9f), ud(0.4f, 8.f);
  KeyFrameRecord r;
  r.seq = 42;
  r.id = 17;
  r.frame_id = 1234;
  r.stamp = 1305031102.175304;
  r.T_wc.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  r.T_wc.translation() = Eigen::Vector3d(0.5, -0.2, 1.3);
  r.camera = {"synthetic_room", 525, 525, 319.5, 239.5, 40.0, 3.05f, 640, 480};
  r.features.descriptors.create(static_cast<int>(n_features), 32, CV_8U);
  for (size_t i = 0; i < n_features; ++i) {
    r.features.keypoints.emplace_back(ux(rng), uy(rng), 31.f, ua(rng), 0.f, static_cast<int>(i % 8));
    r.features.depth.push_back(i % 5 == 0 ? 0.f : ud(rng));
    for (int b = 0; b < 32; ++b) r.features.descriptors.at<uint8_t>(static_cast<int>(i), b) = rng() & 0xFF;
  }
  for (size_t i = 0; i < n_obs; ++i) r.observations.emplace_back(static_cast<uint32_t>(i), 1000 + i);
  for (size_t i = 0; i < n_new; ++i)
    r.new_points.push_back({static_cast<uint32_t>(5000 + i), static_cast<uint32_t>(n_obs + i),
                            Eigen::Vector3f(0.1f * i, 1.f, 2.f)});
  r.parent_id = 16;
  r.covisibility = {{16, 320}, {12, 40}};
  r.refuted_points = {4990, 4991};  // two of KeyFrame 16's new points, rarely found since
  return r;
}

TEST(BridgeConversion, KeyFrameRoundTripWithinQuantisation) {
  const KeyFrameRecord in = make_keyframe(1000, 400, 200);
  const edge_slam_msgs::KeyFrame msg = to_message(in);
  KeyFrameRecord out;
  const DecodeStatus s = from_message(msg, out);
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(out.id, in.id);
  EXPECT_EQ(out.seq, in.seq);
  EXPECT_NEAR(out.stamp, in.stamp, 1e-6);
  EXPECT_TRUE(out.T_wc.isApprox(in.T_wc, 1e-9));
  ASSERT_EQ(out.features.size(), in.features.size());
  for (size_t i = 0; i < in.features.size(); ++i) {
    EXPECT_NEAR(out.features.keypoints[i].pt.x, in.features.keypoints[i].pt.x, 1.0 / 16);
    EXPECT_NEAR(out.features.keypoints[i].pt.y, in.features.keypoints[i].pt.y, 1.0 / 16);
    EXPECT_EQ(out.features.keypoints[i].octave, in.features.keypoints[i].octave);
    const float da = std::fabs(out.features.keypoints[i].angle - in.features.keypoints[i].angle);
    EXPECT_LT(std::min(da, 360.f - da), 0.71f);
    EXPECT_NEAR(out.features.depth[i], in.features.depth[i], 1.0 / 8000);
  }
  EXPECT_EQ(cv::norm(out.features.descriptors, in.features.descriptors, cv::NORM_HAMMING), 0);
  EXPECT_EQ(out.observations, in.observations);
  ASSERT_EQ(out.new_points.size(), in.new_points.size());
  EXPECT_EQ(out.new_points[3].id, in.new_points[3].id);
  EXPECT_TRUE(out.new_points[3].position.isApprox(in.new_points[3].position));
  EXPECT_EQ(out.covisibility, in.covisibility);
  EXPECT_EQ(out.parent_id, in.parent_id);
  ASSERT_EQ(in.refuted_points.size(), 2u);
  EXPECT_EQ(out.refuted_points, in.refuted_points);
}

TEST(BridgeConversion, KeyFrameWireSizeIsCompact) {
  const edge_slam_msgs::KeyFrame msg = to_message(make_keyframe(1000, 400, 200));
  const uint32_t bytes = ros::serialization::serializationLength(msg);
  // 32 KB of descriptors dominate; everything else is a few bytes per keypoint.
  EXPECT_LT(bytes, 48u * 1024u);
  std::cout << "KeyFrame wire size at 1000 features, 400 observations, 200 new points: " << bytes << " bytes\n";
}

// The mobile's new points are its keypoints back-projected (tracking's KeyFrame creation).
KeyFrameRecord with_back_projected_points(KeyFrameRecord r) {
  for (NewPointRecord& p : r.new_points) {
    for (; p.kp_index < r.features.size() && !(r.features.depth[p.kp_index] > 0); ++p.kp_index) {}
    p.position = back_projected_keypoint(r, p.kp_index).value().cast<float>();
  }
  return r;
}

TEST(BridgeConversion, NewPointPositionsThatTheKeypointsImplyAreLeftOutAndComputedBack) {
  KeyFrameRecord in = make_keyframe(1000, 400, 0);
  for (uint32_t i = 0; i < 200; ++i) in.new_points.push_back({5000 + i, 400 + 2 * i, {}});  // kp 400, 402, ...
  in = with_back_projected_points(in);
  const edge_slam_msgs::KeyFrame msg = to_message(in);
  EXPECT_TRUE(msg.new_point_xyz.empty());
  EXPECT_TRUE(msg.new_point_id.empty()) << "ids counting up in keypoint order are implied";
  EXPECT_EQ(msg.new_point_first_id, 5000u);
  KeyFrameRecord out;
  const DecodeStatus s = from_message(msg, out);
  ASSERT_TRUE(s.ok) << s.error;
  ASSERT_EQ(out.new_points.size(), in.new_points.size());
  double worst = 0;
  for (size_t i = 0; i < in.new_points.size(); ++i) {
    EXPECT_EQ(out.new_points[i].id, in.new_points[i].id);
    EXPECT_EQ(out.new_points[i].kp_index, in.new_points[i].kp_index);
    worst = std::max(worst, double((out.new_points[i].position - in.new_points[i].position).norm()));
  }
  EXPECT_LE(worst, kNewPointPositionTolerance) << "depths up to 8 m: within the quantisation";
  EXPECT_GT(worst, 0.0) << "computed from the quantised keypoints, not copied";
  // 12 bytes a point fewer than the same KeyFrame with one position that is not a back-projection.
  KeyFrameRecord moved = in;
  moved.new_points[7].position.x() += 0.01f;
  const edge_slam_msgs::KeyFrame full = to_message(moved);
  ASSERT_EQ(full.new_point_xyz.size(), 3u * 200u) << "all positions or none";
  EXPECT_EQ(ros::serialization::serializationLength(full) - ros::serialization::serializationLength(msg), 12u * 200u);
  ASSERT_TRUE(from_message(full, out).ok);
  EXPECT_TRUE(out.new_points[7].position.isApprox(moved.new_points[7].position)) << "sent as it is";
}

TEST(BridgeConversion, ANewPointWithoutPositionNeedsItsKeypointsDepth) {
  KeyFrameRecord in = make_keyframe(50, 20, 0);
  in.new_points.push_back({5000, 21, {}});
  in = with_back_projected_points(in);
  edge_slam_msgs::KeyFrame msg = to_message(in);
  ASSERT_TRUE(msg.new_point_xyz.empty());
  KeyFrameRecord out;
  ASSERT_TRUE(from_message(msg, out).ok);
  {  // the keypoint lost its depth on the way
    std::vector<WireKeypoint> kps;
    std::string error;
    ASSERT_TRUE(decode_keypoints(msg.keypoints.data(), msg.keypoints.size(), 50, kps, error)) << error;
    kps[21].depth = 0;
    msg.keypoints = encode_keypoints(kps);
  }
  const DecodeStatus s = from_message(msg, out);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("no depth"), std::string::npos) << s.error;
}

// Format 5: the new points' sources travel as a bit per keypoint and their ids as the first
// one when they count up in keypoint order; anything else keeps its ids, in keypoint order.
TEST(BridgeConversion, NewPointSourcesAsAMaskAndIdsCountingUpAsTheFirstOne) {
  KeyFrameRecord in = make_keyframe(1000, 400, 0);
  for (uint32_t i = 0; i < 300; ++i) in.new_points.push_back({7000 + i, 400 + 2 * i, Eigen::Vector3f(0.1f * i, 1.f, 2.f)});
  const edge_slam_msgs::KeyFrame implied = to_message(in);
  ASSERT_EQ(implied.new_point_kp_mask.size(), 125u);
  EXPECT_TRUE(implied.new_point_id.empty());
  EXPECT_EQ(implied.new_point_first_id, 7000u);
  KeyFrameRecord out;
  ASSERT_TRUE(from_message(implied, out).ok);
  ASSERT_EQ(out.new_points.size(), 300u);
  for (size_t i = 0; i < 300; ++i) {
    EXPECT_EQ(out.new_points[i].id, in.new_points[i].id);
    EXPECT_EQ(out.new_points[i].kp_index, in.new_points[i].kp_index);
  }
  // Against format 4's 6 bytes a point (a 4-byte id and a 2-byte index), at 300 points.
  EXPECT_LE(ros::serialization::serializationLength(implied) + 300u * 6u - 125u - 4u,
            ros::serialization::serializationLength(to_message(make_keyframe(1000, 400, 0))) + 300u * 12u + 300u * 6u);

  // Ids that do not count up, listed out of keypoint order: sent one by one, back in keypoint order.
  KeyFrameRecord shuffled = in;
  std::swap(shuffled.new_points[3].id, shuffled.new_points[9].id);
  std::reverse(shuffled.new_points.begin(), shuffled.new_points.end());
  const edge_slam_msgs::KeyFrame explicit_ids = to_message(shuffled);
  EXPECT_EQ(explicit_ids.new_point_id.size(), 300u);
  ASSERT_TRUE(from_message(explicit_ids, out).ok);
  ASSERT_EQ(out.new_points.size(), 300u);
  for (size_t i = 0; i < 300; ++i) {
    EXPECT_EQ(out.new_points[i].kp_index, 400u + 2u * i) << "keypoint order";
    const uint32_t expected = i == 3 ? 7009u : i == 9 ? 7003u : 7000u + static_cast<uint32_t>(i);
    EXPECT_EQ(out.new_points[i].id, expected);
  }

  // A record with two new points at one keypoint cannot be said by the mask: the receiver refuses it.
  KeyFrameRecord twice = in;
  twice.new_points[1].kp_index = twice.new_points[0].kp_index;
  const DecodeStatus s = from_message(to_message(twice), out);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("disagree"), std::string::npos) << s.error;
}

// Format 5: refuted ids within a range travel as a bit mask when that is smaller than the list.
// Format 5: the observed keypoints as a mask, the point ids in keypoint order.
TEST(BridgeConversion, ObservationsInKeypointOrderAsAMaskAndTheirIds) {
  KeyFrameRecord in = make_keyframe(1000, 0, 0);
  for (uint32_t i = 0; i < 300; ++i) in.observations.emplace_back(999 - 3 * i, 20000 + 7 * i);  // descending keypoints
  const edge_slam_msgs::KeyFrame msg = to_message(in);
  EXPECT_EQ(msg.obs_kp_mask.size(), 125u);
  KeyFrameRecord out;
  ASSERT_TRUE(from_message(msg, out).ok);
  std::vector<std::pair<uint32_t, uint32_t>> sorted = in.observations;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(out.observations, sorted) << "the same pairs, in keypoint order";

  KeyFrameRecord twice = in;
  twice.observations.emplace_back(999, 55555);  // a second point at one keypoint: the mask cannot say it
  const DecodeStatus s = from_message(to_message(twice), out);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("obs_point_id has 301"), std::string::npos) << s.error;
}

TEST(BridgeConversion, RefutedPointsAsAMaskOverTheirRangeWhenThatIsSmaller) {
  KeyFrameRecord in = make_keyframe(100, 20, 0);
  in.refuted_points.clear();
  for (uint32_t id = 90000; id < 91500; id += 3) in.refuted_points.push_back(id);  // 500 of 1500 ids
  std::reverse(in.refuted_points.begin(), in.refuted_points.end());
  const edge_slam_msgs::KeyFrame msg = to_message(in);
  EXPECT_TRUE(msg.refuted_point_ids.empty());
  EXPECT_EQ(msg.refuted_first_id, 90000u);
  EXPECT_EQ(msg.refuted_mask.size(), 188u) << "1498 bits";
  KeyFrameRecord out;
  ASSERT_TRUE(from_message(msg, out).ok);
  std::vector<uint32_t> sorted = in.refuted_points;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(out.refuted_points, sorted) << "the same ids, in increasing order";

  KeyFrameRecord sparse = in;
  sparse.refuted_points = {5, 4000000, 77};
  EXPECT_EQ(to_message(sparse).refuted_point_ids, sparse.refuted_points) << "a list where a mask would be larger";
  ASSERT_TRUE(from_message(to_message(sparse), out).ok);
  EXPECT_EQ(out.refuted_points, sparse.refuted_points);

  KeyFrameRecord repeated = in;
  repeated.refuted_points.push_back(90003);
  const DecodeStatus s = from_message(to_message(repeated), out);
  EXPECT_FALSE(s.ok) << "a repeated id is not lost in the mask: sent as a list and refused";
  EXPECT_NE(s.error.find("is repeated"), std::string::npos) << s.error;
}

TEST(BridgeConversion, RejectsMalformedKeyFrames) {
  const edge_slam_msgs::KeyFrame good = to_message(make_keyframe(50, 20, 10));
  KeyFrameRecord out;
  auto expect_reject = [&](edge_slam_msgs::KeyFrame m, const char* what) {
    const DecodeStatus s = from_message(m, out);
    EXPECT_FALSE(s.ok) << what;
    EXPECT_FALSE(s.error.empty()) << what;
  };
  { auto m = good; m.version = 99; expect_reject(m, "version"); }
  { auto m = good; m.descriptors.pop_back(); expect_reject(m, "descriptor length"); }
  { auto m = good; m.keypoints.push_back(1); expect_reject(m, "keypoint block length"); }
  { auto m = good; m.keypoints.clear(); expect_reject(m, "no keypoint block"); }
  { auto m = good; m.pose.position.x = std::nan(""); expect_reject(m, "NaN pose"); }
  { auto m = good; m.pose.orientation.w = 5; expect_reject(m, "non-unit quaternion"); }
  { auto m = good; m.obs_kp_mask[0] ^= 0x01; expect_reject(m, "observation mask and ids disagree"); }
  { auto m = good; m.obs_kp_mask.pop_back(); expect_reject(m, "observation mask length"); }
  { auto m = good; fixtures::list_observed_ids(m); m.obs_point_id.pop_back(); expect_reject(m, "observation arrays"); }
  { auto m = good; m.new_point_xyz.pop_back(); expect_reject(m, "new point xyz"); }
  { auto m = good; m.new_point_xyz[0] = INFINITY; expect_reject(m, "infinite new point"); }
  { auto m = good; m.intrinsics[0] = 0; expect_reject(m, "fx"); }
  { auto m = good; m.width = 0; expect_reject(m, "width"); }
  { auto m = good; m.id = kNoId; expect_reject(m, "reserved id"); }
  { auto m = good; m.refuted_point_ids = {7, kNoId}; expect_reject(m, "reserved refuted point id"); }
  { auto m = good; m.refuted_point_ids = {7, 7}; expect_reject(m, "repeated refuted point"); }
  { auto m = good; m.refuted_point_ids.assign(20001, 0); expect_reject(m, "too many refuted points"); }
  { auto m = good; m.refuted_mask = {1}, m.refuted_point_ids = {7}; expect_reject(m, "refuted points in both forms"); }
  { auto m = good; m.refuted_mask = {0x80}, m.refuted_first_id = kNoId - 7; expect_reject(m, "mask reaching the reserved id"); }
  { auto m = good; m.refuted_mask.assign(2501, 0xff), m.refuted_first_id = 10; expect_reject(m, "too many refuted points (mask)"); }
  EXPECT_EQ(out.id, kNoId) << "a rejected message must leave the output untouched";
}

TEST(BridgeConversion, MapUpdateRoundTripAndRejection) {
  MapUpdateRecord in;
  in.kind = MapUpdateKind::kRelocalization;
  in.seq = 3;
  in.request_frame_id = 99;
  in.last_keyframe_seq = 41;
  for (uint32_t k = 0; k < 6; ++k) {
    in.keyframes.push_back(make_keyframe(100, 50, 0, k));
    in.keyframes.back().id = 100 + k;  // an update holds each KeyFrame once
  }
  for (uint32_t i = 0; i < 300; ++i) {
    MapPointRecord p;
    p.id = 1000 + i;
    p.position = {0.01f * i, 1, 2};
    p.normal = {0, 0, -1};
    p.descriptor.fill(static_cast<uint8_t>(i));
    p.min_distance = 0.5f;
    p.max_distance = 4.f;
    p.ref_keyframe_id = 17;
    in.points.push_back(p);
  }
  const edge_slam_msgs::MapUpdate msg = to_message(in);
  MapUpdateRecord out;
  ASSERT_TRUE(from_message(msg, out).ok);
  EXPECT_EQ(out.kind, MapUpdateKind::kRelocalization);
  EXPECT_EQ(out.request_frame_id, 99u);
  EXPECT_EQ(out.keyframes.size(), 6u);
  ASSERT_EQ(out.points.size(), 300u);
  EXPECT_EQ(out.points[7].descriptor, in.points[7].descriptor);
  EXPECT_TRUE(out.points[7].position.isApprox(in.points[7].position));

  auto bad = msg;
  bad.points.normals.pop_back();
  EXPECT_FALSE(from_message(bad, out).ok);
  bad = msg;
  bad.kind = 7;
  EXPECT_FALSE(from_message(bad, out).ok);
  bad = msg;
  bad.keyframes[2].descriptors.resize(3);
  const DecodeStatus s = from_message(bad, out);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("keyframes[2]"), std::string::npos) << s.error;
}

}  // namespace
}  // namespace edge_slam
