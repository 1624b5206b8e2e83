// Bytes -> message with the array lengths checked before roscpp allocates: valid messages
// come back equal, truncated / padded / length-lying bytes are refused with a reason, and
// the walk is pinned to the message definitions it mirrors.
#include <edge_slam_bridge/checked_deserialization.h>
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include <cstring>

#include "support/wire_fixtures.h"

namespace edge_slam {
namespace {

// wire_layout.h follows these definitions field by field: when a .msg file changes, its
// MD5 changes and this test says to update the walk (then the sums here).
TEST(CheckedDeserialization, WalkMatchesTheMessageDefinitions) {
  EXPECT_STREQ(ros::message_traits::MD5Sum<edge_slam_msgs::KeyFrame>::value(), "aa03f1f6e3056a982c17d75e948b4403");
  EXPECT_STREQ(ros::message_traits::MD5Sum<edge_slam_msgs::Frame>::value(), "e344cca141c2b38a22ac444ca2671484");
  EXPECT_STREQ(ros::message_traits::MD5Sum<edge_slam_msgs::MapUpdate>::value(), "2b69d5cefe585a0199c8a0c06dd7febc");
}

TEST(CheckedDeserialization, ValidBytesComeBackEqual) {
  const edge_slam_msgs::KeyFrame kf = to_message(fixtures::keyframe(3, 70, 30, 12));
  edge_slam_msgs::KeyFrame kf_out;
  DecodeStatus s = deserialize_checked(fixtures::serialized(kf).data(), fixtures::serialized(kf).size(), kf_out);
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(fixtures::serialized(kf_out), fixtures::serialized(kf));

  const edge_slam_msgs::Frame frame = to_message(fixtures::frame(90));
  edge_slam_msgs::Frame frame_out;
  s = deserialize_checked(fixtures::serialized(frame).data(), fixtures::serialized(frame).size(), frame_out);
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(fixtures::serialized(frame_out), fixtures::serialized(frame));

  const edge_slam_msgs::MapUpdate update = to_message(fixtures::map_update(5, 40, 25));
  edge_slam_msgs::MapUpdate update_out;
  const std::vector<uint8_t> b = fixtures::serialized(update);
  s = deserialize_checked(b.data(), b.size(), update_out);
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(fixtures::serialized(update_out), b);
}

TEST(CheckedDeserialization, TruncatedPaddedAndLyingBytesAreRefused) {
  const std::vector<uint8_t> good = fixtures::serialized(to_message(fixtures::keyframe(3, 70, 30, 12)));
  edge_slam_msgs::KeyFrame out;
  for (size_t cut : {size_t{0}, size_t{1}, size_t{50}, good.size() / 2, good.size() - 1}) {
    const DecodeStatus s = deserialize_checked(good.data(), cut, out);
    EXPECT_FALSE(s.ok) << "cut at " << cut;
    EXPECT_NE(s.error.find("truncated"), std::string::npos) << s.error;
  }
  std::vector<uint8_t> padded = good;
  padded.push_back(0);
  DecodeStatus s = deserialize_checked(padded.data(), padded.size(), out);
  EXPECT_NE(s.error.find("trailing"), std::string::npos) << s.error;

  // The keypoint block's length field (after 90 fixed bytes and the camera name) claims 2^31 bytes:
  // roscpp alone would try to allocate 4 GiB here.
  std::vector<uint8_t> lying = good;
  const size_t name_length_at = 1 + 8 + 4 + 4 + 8 + 8 + 1 + 56;
  uint32_t name_length = 0;
  std::memcpy(&name_length, &lying[name_length_at], 4);
  const size_t keypoints_at = name_length_at + 4 + name_length + 48;
  const uint32_t huge = 0x80000000u;
  std::memcpy(&lying[keypoints_at], &huge, 4);
  s = deserialize_checked(lying.data(), lying.size(), out);
  EXPECT_FALSE(s.ok);
  EXPECT_NE(s.error.find("keypoints"), std::string::npos) << s.error;

  const std::vector<uint8_t> update = fixtures::serialized(to_message(fixtures::map_update(2, 10, 5)));
  edge_slam_msgs::MapUpdate update_out;
  std::vector<uint8_t> many = update;
  const uint32_t claimed = 100000;  // KeyFrames that cannot fit in the bytes that follow
  std::memcpy(&many[1 + 1 + 8 + 4 + 8 + 8 + 8], &claimed, 4);
  s = deserialize_checked(many.data(), many.size(), update_out);
  EXPECT_NE(s.error.find("keyframes"), std::string::npos) << s.error;

  MessageLimits small;
  small.max_message_bytes = 100;
  s = deserialize_checked(update.data(), update.size(), update_out, small);
  EXPECT_NE(s.error.find("exceeds"), std::string::npos) << s.error;
}

}  // namespace
}  // namespace edge_slam
