// Each field rule of the message -> record decoding rejects its violation with a reason that
// names the field, and leaves the output untouched.
#include <edge_slam_bridge/message_conversion.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "support/wire_fixtures.h"

namespace edge_slam {
namespace {

template <class Msg, class Record>
void expect_rejected(const Msg& good, const std::function<void(Msg&)>& spoil, const char* word,
                     const MessageLimits& limits = MessageLimits()) {
  Msg m = good;
  spoil(m);
  Record out;
  out.seq = 4242;
  const DecodeStatus s = from_message(m, out, limits);
  EXPECT_FALSE(s.ok) << "accepted; expected an error about '" << word << "'";
  EXPECT_NE(s.error.find(word), std::string::npos) << "error '" << s.error << "' does not mention '" << word << "'";
  EXPECT_EQ(out.seq, 4242u) << "a rejected message must leave the output untouched";
}

using KfMsg = edge_slam_msgs::KeyFrame;
using FrameMsg = edge_slam_msgs::Frame;
using UpdateMsg = edge_slam_msgs::MapUpdate;

void kf_rejected(const std::function<void(KfMsg&)>& spoil, const char* word, const MessageLimits& l = {}) {
  static const KfMsg good = to_message(fixtures::keyframe(7, 60, 20, 10));
  expect_rejected<KfMsg, KeyFrameRecord>(good, spoil, word, l);
}

TEST(BridgeValidation, GoodMessagesDecode) {
  KeyFrameRecord kf;
  EXPECT_TRUE(from_message(to_message(fixtures::keyframe(7, 60, 20, 10)), kf).ok);
  FrameRecord f;
  EXPECT_TRUE(from_message(to_message(fixtures::frame(80)), f).ok);
  MapUpdateRecord u;
  const DecodeStatus s = from_message(to_message(fixtures::map_update(4, 50, 30)), u);
  EXPECT_TRUE(s.ok) << s.error;
}

TEST(BridgeValidation, KeyFrameHeaderPoseAndCamera) {
  kf_rejected([](KfMsg& m) { m.version = 1; }, "version");  // the format before the decision counts
  kf_rejected([](KfMsg& m) { m.id = kNoId; }, "reserved");
  kf_rejected([](KfMsg& m) { m.created_wall = NAN; }, "created_wall");
  kf_rejected([](KfMsg& m) { m.pose.position.z = INFINITY; }, "pose");
  kf_rejected([](KfMsg& m) { m.pose.orientation.x = NAN; }, "pose");
  kf_rejected([](KfMsg& m) { m.pose.orientation.w = 0.5; }, "quaternion");
  kf_rejected([](KfMsg& m) { m.pose.position.x = 1e12; }, "range");
  kf_rejected([](KfMsg& m) { m.intrinsics[2] = NAN; }, "intrinsics[2]");
  kf_rejected([](KfMsg& m) { m.intrinsics[1] = -5; }, "fx, fy");
  kf_rejected([](KfMsg& m) { m.bf = -1; }, "bf");
  kf_rejected([](KfMsg& m) { m.th_depth = NAN; }, "th_depth");
  kf_rejected([](KfMsg& m) { m.height = 0; }, "width/height");
  kf_rejected([](KfMsg& m) { m.width = 9000; }, "width/height");
  kf_rejected([](KfMsg& m) { m.camera_name.assign(300, 'c'); }, "camera_name");
}

TEST(BridgeValidation, KeyFrameFeatureArrays) {
  kf_rejected([](KfMsg& m) { m.keypoints.pop_back(); }, "keypoints: truncated");
  kf_rejected([](KfMsg& m) { m.keypoints.push_back(0); }, "after the last keypoint");
  kf_rejected([](KfMsg& m) { m.keypoints.clear(); }, "header");
  kf_rejected([](KfMsg& m) { m.keypoints[7] = 40; }, "octave 40");  // the first run's level
  kf_rejected([](KfMsg& m) { m.descriptors.pop_back(); }, "32 per keypoint");
  kf_rejected([](KfMsg& m) { m.descriptors.resize(m.descriptors.size() - 32); }, "59 keypoints");
  MessageLimits few;
  few.max_keypoints = 50;
  kf_rejected([](KfMsg&) {}, "too many keypoints", few);
}

TEST(BridgeValidation, KeyFrameObservationsAndNewPoints) {
  kf_rejected([](KfMsg& m) { fixtures::list_observed_ids(m); m.obs_point_id.pop_back(); }, "obs_point_id has");
  kf_rejected([](KfMsg& m) { fixtures::list_observed_ids(m); m.obs_kp_mask[0] ^= 0x01; }, "obs_point_id has");  // a keypoint more or less
  // The packed ids (format 6): a keypoint more or less in the mask, both forms, a truncated
  // block, an id outside its class.
  kf_rejected([](KfMsg& m) {  // one keypoint more: the block holds one id too few
    size_t k = 0;
    while (m.obs_kp_mask[k / 8] & (1u << (k % 8))) ++k;
    m.obs_kp_mask[k / 8] |= static_cast<uint8_t>(1u << (k % 8));
  }, "obs_point_id_packed");
  kf_rejected([](KfMsg& m) { m.obs_point_id.push_back(5); }, "both obs_point_id and obs_point_id_packed");
  kf_rejected([](KfMsg& m) { m.obs_point_id_packed.resize(8); }, "header");
  kf_rejected([](KfMsg& m) { m.obs_point_id_packed.pop_back(); }, "truncated at id");
  kf_rejected([](KfMsg& m) { m.obs_point_id_packed[4] = 0x80; }, "outside its class");  // low base from 2^31
  kf_rejected([](KfMsg& m) { m.obs_kp_mask.back() |= 0x80; }, "past the 60 keypoints");
  kf_rejected([](KfMsg& m) { m.obs_kp_mask.push_back(0); }, "obs_kp_mask has 9 bytes");
  kf_rejected([](KfMsg& m) { fixtures::list_observed_ids(m); m.obs_point_id[2] = kNoId; }, "reserved point id");
  kf_rejected([](KfMsg& m) { fixtures::list_observed_ids(m); m.obs_point_id[1] = m.obs_point_id[0]; }, "repeats point");
  kf_rejected([](KfMsg& m) {  // keypoint 16 sees a point and is made the source of a new one too
    m.new_point_kp_mask[2] |= 0x01;
    m.new_point_xyz.insert(m.new_point_xyz.begin(), {0.3f, 0.1f, 1.2f});
  }, "reuses keypoint");
  kf_rejected([](KfMsg& m) { m.new_point_xyz.pop_back(); }, "new_point arrays");
  kf_rejected([](KfMsg& m) { m.new_point_kp_mask[3] ^= 0x01; }, "new_point arrays");  // one source more or less
  kf_rejected([](KfMsg& m) { m.new_point_kp_mask.pop_back(); }, "new_point_kp_mask");
  kf_rejected([](KfMsg& m) { m.new_point_kp_mask.push_back(0); }, "new_point_kp_mask");
  kf_rejected([](KfMsg& m) { m.new_point_id.clear(), m.new_point_first_id = kNoId - 3; }, "reserved id");
  kf_rejected([](KfMsg& m) { fixtures::list_observed_ids(m); m.new_point_id.clear(), m.new_point_first_id = m.obs_point_id[0]; }, "repeats point");
  kf_rejected([](KfMsg& m) { m.new_point_id.push_back(12345); }, "new_point arrays");
  kf_rejected([](KfMsg& m) { m.new_point_id.assign(m.new_point_xyz.size() / 3, 900), m.new_point_id[0] = kNoId; }, "reserved id");
  kf_rejected([](KfMsg& m) { m.new_point_id.assign(m.new_point_xyz.size() / 3, 900); }, "repeats point");
  kf_rejected([](KfMsg& m) { m.new_point_xyz[4] = NAN; }, "not finite");
  kf_rejected([](KfMsg& m) { m.new_point_xyz[4] = 1e30f; }, "out of range");
  MessageLimits few;
  few.max_new_points = 5;
  kf_rejected([](KfMsg&) {}, "too many new points", few);
}

TEST(BridgeValidation, KeyFrameLinks) {
  kf_rejected([](KfMsg& m) { m.parent_id = m.id; }, "own parent");
  kf_rejected([](KfMsg& m) { m.covis_weights.pop_back(); }, "differ in length");
  kf_rejected([](KfMsg& m) { m.covis_ids[0] = m.id; }, "covis_ids[0]");
  kf_rejected([](KfMsg& m) { m.covis_ids[0] = kNoId; }, "covis_ids[0]");
  kf_rejected([](KfMsg& m) { m.covis_ids.push_back(m.covis_ids[0]), m.covis_weights.push_back(1); },
              "repeated covisibility");
  MessageLimits few;
  few.max_covisibility = 0;
  kf_rejected([](KfMsg&) {}, "too many covisibility", few);
  few = MessageLimits();
  few.max_message_bytes = 1000;
  kf_rejected([](KfMsg&) {}, "exceeds", few);
}

TEST(BridgeValidation, FrameFields) {
  static const FrameMsg good = to_message(fixtures::frame(40));
  auto rejected = [](const std::function<void(FrameMsg&)>& spoil, const char* word, const MessageLimits& l = {}) {
    expect_rejected<FrameMsg, FrameRecord>(good, spoil, word, l);
  };
  rejected([](FrameMsg& m) { m.version = 0; }, "version");
  rejected([](FrameMsg& m) { m.created_wall = -INFINITY; }, "created_wall");
  rejected([](FrameMsg& m) { m.keypoints.clear(); }, "keypoints");
  rejected([](FrameMsg& m) { m.descriptors.push_back(1); }, "32 per keypoint");
  rejected([](FrameMsg& m) { m.intrinsics[0] = 0; }, "fx, fy");
  rejected([](FrameMsg& m) { m.keypoints[7] = 200; }, "octave 200");
  MessageLimits few;
  few.max_keypoints = 10;
  rejected([](FrameMsg&) {}, "too many keypoints", few);
}

TEST(BridgeValidation, MapUpdateFields) {
  static const UpdateMsg good = to_message(fixtures::map_update(4, 50, 30));
  auto rejected = [](const std::function<void(UpdateMsg&)>& spoil, const char* word, const MessageLimits& l = {}) {
    expect_rejected<UpdateMsg, MapUpdateRecord>(good, spoil, word, l);
  };
  rejected([](UpdateMsg& m) { m.version = 9; }, "version");
  rejected([](UpdateMsg& m) { m.kind = 2; }, "kind");
  rejected([](UpdateMsg& m) { m.keyframes[1].id = m.keyframes[2].id; }, "repeats");
  rejected([](UpdateMsg& m) { m.keyframes[0].parent_id = 3; }, "cycle");
  rejected([](UpdateMsg& m) { m.keyframes[3].keypoints.pop_back(); }, "keyframes[3]");
  rejected([](UpdateMsg& m) { m.points.ids[4] = m.points.ids[3]; }, "repeats");
  rejected([](UpdateMsg& m) { m.points.ids[4] = kNoId; }, "reserved");
  rejected([](UpdateMsg& m) { m.points.positions[7] = NAN; }, "non-finite");
  rejected([](UpdateMsg& m) { m.points.normals[7] = 5; }, "normal");
  rejected([](UpdateMsg& m) { m.points.distances[0] = 9; }, "distance");
  rejected([](UpdateMsg& m) { m.points.descriptors.pop_back(); }, "32 descriptor bytes");
  rejected([](UpdateMsg& m) { m.points.ref_keyframe_ids.pop_back(); }, "disagree");
  MessageLimits few;
  few.max_keyframes_per_update = 3;
  rejected([](UpdateMsg&) {}, "too many KeyFrames", few);
  few = MessageLimits();
  few.max_points_per_update = 29;
  rejected([](UpdateMsg&) {}, "too many points", few);
  few = MessageLimits();
  few.max_message_bytes = 4096;
  rejected([](UpdateMsg&) {}, "exceeds", few);
}

}  // namespace
}  // namespace edge_slam
