// RawMessage<M>: what the nodelets subscribe with, so they decode the bytes themselves. It must
// look like M to roscpp (type, MD5, definition) and keep the bytes exactly.
#include <edge_slam_bridge/checked_deserialization.h>
#include <edge_slam_bridge/raw_message.h>
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include "support/wire_fixtures.h"

namespace edge_slam {
namespace {

TEST(RawMessage, NegotiatesAsTheMessageItCarries) {
  using Raw = RawMessage<edge_slam_msgs::KeyFrame>;
  EXPECT_STREQ(ros::message_traits::md5sum<Raw>(), ros::message_traits::md5sum<edge_slam_msgs::KeyFrame>());
  EXPECT_STREQ(ros::message_traits::datatype<Raw>(), "edge_slam_msgs/KeyFrame");
  EXPECT_STREQ(ros::message_traits::definition<Raw>(), ros::message_traits::definition<edge_slam_msgs::KeyFrame>());
}

TEST(RawMessage, KeepsTheBytesForCheckedDecoding) {
  const edge_slam_msgs::MapUpdate update = to_message(fixtures::map_update(3, 20, 10));
  // What roscpp does with a received buffer: deserialize it into the subscribed type.
  ros::SerializedMessage wire = ros::serialization::serializeMessage(update);
  RawMessage<edge_slam_msgs::MapUpdate> raw;
  ros::serialization::deserializeMessage(wire, raw);
  ASSERT_EQ(raw.bytes.size(), ros::serialization::serializationLength(update));
  edge_slam_msgs::MapUpdate decoded;
  const DecodeStatus s = deserialize_checked(raw.bytes.data(), raw.bytes.size(), decoded);
  ASSERT_TRUE(s.ok) << s.error;
  EXPECT_EQ(decoded.keyframes.size(), 3u);

  raw.bytes.resize(raw.bytes.size() - 1);  // a truncated message is refused, not thrown or crashed on
  EXPECT_FALSE(deserialize_checked(raw.bytes.data(), raw.bytes.size(), decoded).ok);
}

}  // namespace
}  // namespace edge_slam
