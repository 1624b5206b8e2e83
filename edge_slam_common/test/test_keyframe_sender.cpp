// The mobile's KeyFrame sender (split/keyframe_sender.h), with time as an argument: records go
// from the outbox through the resend queue, out once each, resent when unacknowledged, held
// while nobody listens; the floor goes out every 0.2 s; the bound drops the oldest (counted).
#include <gtest/gtest.h>

#include "edge_slam/split/keyframe_sender.h"
#include "support/delivery_records.h"

namespace edge_slam {
namespace {

using test_support::delivery_ack;

KeyFrameRecord record(uint64_t seq) { return test_support::delivery_record(seq); }

std::vector<uint64_t> seqs(const KeyFrameSender::Due& due) {
  std::vector<uint64_t> out;
  for (const auto& r : due.records) out.push_back(r->seq);
  return out;
}

KeyFrameAck ack(uint64_t boot, uint64_t received, uint64_t durable) { return delivery_ack(boot, received, durable); }

constexpr std::chrono::milliseconds kNoWait{0};

TEST(KeyFrameSender, OutboxRecordsGoOutOnceInOrderWithTheFloor) {
  BoundedQueue<KeyFrameRecord> outbox(10);
  for (uint64_t s = 1; s <= 3; ++s) outbox.push(record(s));
  KeyFrameSender sender;
  EXPECT_EQ(sender.take_from(outbox, kNoWait, 0.0), 3u);
  EXPECT_EQ(outbox.size(), 0u);
  const KeyFrameSender::Due first = sender.due(10.0, true);
  EXPECT_EQ(seqs(first), (std::vector<uint64_t>{1, 2, 3}));
  ASSERT_TRUE(first.floor.has_value()) << "the first step publishes the floor";
  EXPECT_EQ(*first.floor, 0u) << "nothing freed yet";
  const KeyFrameSender::Due soon = sender.due(10.1, true);
  EXPECT_TRUE(soon.records.empty()) << "not due again before the resend timeout";
  EXPECT_FALSE(soon.floor.has_value()) << "the floor waits 0.2 s";
  EXPECT_TRUE(sender.due(10.25, true).floor.has_value());
  EXPECT_EQ(sender.counters().sent, 3u);
}

TEST(KeyFrameSender, NothingIsDueWhileNobodyListensAndAllOfItOnceTheEdgeDoes) {
  BoundedQueue<KeyFrameRecord> outbox(10);
  outbox.push(record(1));
  outbox.push(record(2));
  KeyFrameSender sender;
  sender.take_from(outbox, kNoWait, 0.0);
  const KeyFrameSender::Due silent = sender.due(1.0, false);
  EXPECT_TRUE(silent.records.empty());
  EXPECT_FALSE(silent.floor.has_value());
  EXPECT_EQ(sender.counters().sent, 0u) << "held, not counted as sent";
  EXPECT_EQ(seqs(sender.due(30.0, true)), (std::vector<uint64_t>{1, 2}));
}

TEST(KeyFrameSender, UnacknowledgedRecordsAreResentAndAcknowledgedOnesAreNot) {
  BoundedQueue<KeyFrameRecord> outbox(10);
  for (uint64_t s = 1; s <= 3; ++s) outbox.push(record(s));
  KeyFrameSender sender;  // resend_timeout 1 s
  sender.take_from(outbox, kNoWait, 0.0);
  sender.due(0.0, true);
  EXPECT_FALSE(sender.on_ack(ack(7, 2, 2), 0.5));
  EXPECT_EQ(seqs(sender.due(1.1, true)), (std::vector<uint64_t>{3}));
  EXPECT_EQ(sender.counters().resent, 1u);
  EXPECT_EQ(sender.counters().durable, 2u);
}

TEST(KeyFrameSender, ARestartedEdgeIsReportedAndGetsWhatCameAfterItsCheckpointAtOnce) {
  BoundedQueue<KeyFrameRecord> outbox(10);
  for (uint64_t s = 1; s <= 4; ++s) outbox.push(record(s));
  KeyFrameSender sender;
  sender.take_from(outbox, kNoWait, 0.0);
  sender.due(0.0, true);
  EXPECT_FALSE(sender.on_ack(ack(7, 4, 2), 0.1));
  EXPECT_TRUE(sender.due(0.3, true).records.empty()) << "received: nothing to resend";
  EXPECT_TRUE(sender.on_ack(ack(8, 2, 2), 0.4)) << "a new boot id: the edge restarted from its checkpoint";
  EXPECT_EQ(seqs(sender.due(0.5, true)), (std::vector<uint64_t>{3, 4})) << "at once, not after the timeout";
  EXPECT_EQ(sender.counters().edge_restarts, 1u);
}

TEST(KeyFrameSender, TheBoundDropsTheOldestAndTheFloorPassesIt) {
  BoundedQueue<KeyFrameRecord> outbox(10);
  for (uint64_t s = 1; s <= 3; ++s) outbox.push(record(s));
  DeliveryParams p;
  p.capacity = 2;
  KeyFrameSender sender(p);
  EXPECT_EQ(sender.take_from(outbox, kNoWait, 0.0), 3u);
  EXPECT_EQ(sender.counters().dropped_by_bound, 1u);
  const KeyFrameSender::Due due = sender.due(0.0, true);
  EXPECT_EQ(seqs(due), (std::vector<uint64_t>{2, 3}));
  EXPECT_EQ(*due.floor, 1u) << "the edge must not wait for seq 1";
}

TEST(KeyFrameSender, AnEmptyOutboxReturnsAtOnceWithoutWaiting) {
  BoundedQueue<KeyFrameRecord> outbox(10);
  KeyFrameSender sender;
  EXPECT_EQ(sender.take_from(outbox, kNoWait, 0.0), 0u);
  outbox.close();
  EXPECT_EQ(sender.take_from(outbox, std::chrono::milliseconds(1000), 0.0), 0u) << "a closed outbox does not block";
}

}  // namespace
}  // namespace edge_slam
