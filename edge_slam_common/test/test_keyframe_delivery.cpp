// KeyFrame delivery (module/keyframe_delivery.h, module/keyframe_receipts.h): acknowledgement
// frees, timeouts resend in seq order (backing off; a returning link makes the rest due at once), a restarted edge gets everything after its durable seq,
// the bound drops the oldest (counted), duplicates change nothing, and the mobile's floor lets
// the edge's contiguous seq pass what was dropped.
#include <gtest/gtest.h>

#include "edge_slam/module/keyframe_delivery.h"
#include "edge_slam/module/keyframe_receipts.h"
#include "support/delivery_records.h"

namespace edge_slam {
namespace {

KeyFrameDelivery::RecordPtr record(uint64_t seq) {
  return std::make_shared<KeyFrameRecord>(test_support::delivery_record(seq));
}

std::vector<uint64_t> seqs(const std::vector<KeyFrameDelivery::RecordPtr>& rs) {
  std::vector<uint64_t> out;
  for (const auto& r : rs) out.push_back(r->seq);
  return out;
}

KeyFrameAck ack(uint64_t boot, uint64_t received, uint64_t durable, bool persistent = true) {
  return test_support::delivery_ack(boot, received, durable, persistent);
}

TEST(KeyFrameDelivery, NewRecordsGoOutOnceInOrder) {
  KeyFrameDelivery d;
  for (uint64_t s = 1; s <= 3; ++s) d.add(record(s));
  EXPECT_EQ(seqs(d.take_due(0.0)), (std::vector<uint64_t>{1, 2, 3}));
  EXPECT_TRUE(d.take_due(0.5).empty()) << "not due again before the timeout";
  EXPECT_EQ(d.counters().sent, 3u);
  EXPECT_EQ(d.counters().resent, 0u);
}

TEST(KeyFrameDelivery, AckedRecordsAreNotResentAndDurableOnesFreed) {
  KeyFrameDelivery d;
  for (uint64_t s = 1; s <= 4; ++s) d.add(record(s));
  d.take_due(0.0);
  d.on_ack(ack(7, 3, 1), 0.2);
  DeliveryCounters c = d.counters();
  EXPECT_EQ(c.acknowledged, 3u);
  EXPECT_EQ(c.durable, 1u);
  EXPECT_EQ(c.queued, 3u) << "received but not checkpointed: kept";
  EXPECT_EQ(seqs(d.take_due(1.5)), (std::vector<uint64_t>{4})) << "only the unacknowledged one is resent";
  EXPECT_EQ(d.counters().resent, 1u);
  d.on_ack(ack(7, 4, 4), 1.6);
  EXPECT_EQ(d.counters().queued, 0u);
  EXPECT_EQ(d.counters().durable, 4u);
  EXPECT_EQ(d.floor(), 4u);
  EXPECT_NEAR(d.seconds_since_ack(2.0), 0.4, 1e-9);
}

TEST(KeyFrameDelivery, WithoutPersistenceReceivedIsEnough) {
  KeyFrameDelivery d;
  for (uint64_t s = 1; s <= 3; ++s) d.add(record(s));
  d.take_due(0.0);
  d.on_ack(ack(1, 2, 0, false), 0.1);
  EXPECT_EQ(d.counters().queued, 1u);
  EXPECT_EQ(d.floor(), 2u);
}

TEST(KeyFrameDelivery, TimeoutResendsInSeqOrderBackingOff) {
  DeliveryParams p;
  p.resend_timeout = 1.0;
  p.resend_timeout_max = 4.0;
  KeyFrameDelivery d(p);
  d.add(record(1));
  d.add(record(2));
  d.take_due(0.0);
  d.add(record(3));
  EXPECT_EQ(seqs(d.take_due(0.5)), (std::vector<uint64_t>{3}));
  EXPECT_EQ(seqs(d.take_due(1.0)), (std::vector<uint64_t>{1, 2})) << "first resend after resend_timeout";
  EXPECT_EQ(seqs(d.take_due(1.6)), (std::vector<uint64_t>{3}));
  EXPECT_TRUE(d.take_due(2.1).empty()) << "the next one waits twice as long";
  EXPECT_EQ(seqs(d.take_due(3.0)), (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(seqs(d.take_due(6.9)), (std::vector<uint64_t>{3})) << "3's second resend: its own schedule";
  EXPECT_EQ(seqs(d.take_due(7.0)), (std::vector<uint64_t>{1, 2})) << "then 4 s, the cap";
  EXPECT_TRUE(d.take_due(10.8).empty());
  EXPECT_EQ(seqs(d.take_due(11.0)), (std::vector<uint64_t>{1, 2, 3})) << "4 s again: capped at resend_timeout_max";
  EXPECT_EQ(d.counters().sent, 3u);
  EXPECT_EQ(d.counters().resent, 11u);
}

TEST(KeyFrameDelivery, FirstAckAfterASilenceMakesTheRestDueAtOnce) {
  DeliveryParams p;
  p.resend_timeout = 1.0;
  KeyFrameDelivery d(p);
  for (uint64_t s = 1; s <= 4; ++s) d.add(record(s));
  d.take_due(0.0);
  d.on_ack(ack(1, 1, 1), 0.1);
  d.take_due(1.1);  // 2-4 resent, next wait 2 s
  d.take_due(3.1);  // and again, next wait 4 s: the link is down
  d.on_ack(ack(1, 2, 2), 5.0);  // back after 4.9 s of silence: 3-4 go now, not at 7.1
  EXPECT_EQ(seqs(d.take_due(5.0)), (std::vector<uint64_t>{3, 4}));
  EXPECT_EQ(seqs(d.take_due(6.0)), (std::vector<uint64_t>{3, 4})) << "backoff restarted at resend_timeout";
}

TEST(KeyFrameDelivery, RestartedEdgeGetsEverythingAfterItsDurableSeqAtOnce) {
  KeyFrameDelivery d;
  for (uint64_t s = 1; s <= 6; ++s) d.add(record(s));
  d.take_due(0.0);
  d.on_ack(ack(1, 6, 2), 0.1);  // all received, 1-2 checkpointed
  EXPECT_TRUE(d.take_due(5.0).empty()) << "acknowledged: no resend";
  d.on_ack(ack(2, 2, 2), 5.1);  // a new boot restored from the checkpoint
  EXPECT_EQ(seqs(d.take_due(5.1)), (std::vector<uint64_t>{3, 4, 5, 6})) << "no timeout wait";
  EXPECT_EQ(d.counters().edge_restarts, 1u);
  EXPECT_EQ(d.counters().acknowledged, 6u) << "each record counted acknowledged once";
  d.on_ack(ack(2, 6, 6), 5.3);
  EXPECT_EQ(d.counters().queued, 0u);
}

TEST(KeyFrameDelivery, RestartedEmptyEdgeGetsAllHeldRecords) {
  KeyFrameDelivery d;
  for (uint64_t s = 1; s <= 3; ++s) d.add(record(s));
  d.take_due(0.0);
  d.on_ack(ack(1, 3, 0), 0.1);
  d.on_ack(ack(2, 0, 0), 0.2);
  EXPECT_EQ(seqs(d.take_due(0.2)), (std::vector<uint64_t>{1, 2, 3}));
}

TEST(KeyFrameDelivery, BoundDropsTheOldestAndCountsIt) {
  DeliveryParams p;
  p.capacity = 3;
  KeyFrameDelivery d(p);
  EXPECT_TRUE(d.add(record(1)));
  d.add(record(2));
  d.add(record(3));
  EXPECT_FALSE(d.add(record(4)));
  EXPECT_FALSE(d.add(record(5)));
  const DeliveryCounters c = d.counters();
  EXPECT_EQ(c.dropped_by_bound, 2u);
  EXPECT_EQ(c.queued, 3u);
  EXPECT_EQ(seqs(d.take_due(0.0)), (std::vector<uint64_t>{3, 4, 5}));
  EXPECT_EQ(d.floor(), 2u) << "the edge may skip what was dropped";
}

TEST(KeyFrameDelivery, DuplicateAndStaleAcksChangeNothing) {
  KeyFrameDelivery d;
  for (uint64_t s = 1; s <= 3; ++s) d.add(record(s));
  d.take_due(0.0);
  d.on_ack(ack(1, 3, 1), 0.1);
  d.on_ack(ack(1, 3, 1), 0.2);
  d.on_ack(ack(1, 2, 0), 0.3);  // an older ack arriving late: nothing comes back
  const DeliveryCounters c = d.counters();
  EXPECT_EQ(c.acknowledged, 3u);
  EXPECT_EQ(c.durable, 1u);
  EXPECT_EQ(c.queued, 2u);
  EXPECT_EQ(c.acks, 3u);
}

TEST(KeyFrameDelivery, RejectsBadParameters) {
  DeliveryParams p;
  p.capacity = 0;
  EXPECT_THROW(KeyFrameDelivery{p}, std::invalid_argument);
  p.capacity = 1;
  p.resend_timeout = 0;
  EXPECT_THROW(KeyFrameDelivery{p}, std::invalid_argument);
  p.resend_timeout = 2.0;
  p.resend_timeout_max = 1.0;
  EXPECT_THROW(KeyFrameDelivery{p}, std::invalid_argument) << "the cap below the first timeout";
}

TEST(KeyFrameReceipts, ContiguousSeqOverOutOfOrderAndDuplicates) {
  KeyFrameReceipts r;
  r.mark(2);
  EXPECT_EQ(r.contiguous(), 0u);
  r.mark(1);
  EXPECT_EQ(r.contiguous(), 2u);
  r.mark(2);
  r.mark(4);
  EXPECT_EQ(r.contiguous(), 2u);
  r.mark(3);
  EXPECT_EQ(r.contiguous(), 4u);
}

TEST(KeyFrameReceipts, FloorClosesGapsOfDroppedRecords) {
  KeyFrameReceipts r;
  r.mark(1);
  r.mark(5);
  r.mark(6);
  r.skip_through(3);  // the mobile dropped 2-3
  EXPECT_EQ(r.contiguous(), 3u);
  r.skip_through(4);
  EXPECT_EQ(r.contiguous(), 6u);
  r.skip_through(2);
  EXPECT_EQ(r.contiguous(), 6u) << "never goes back";
  r.restore(2);
  EXPECT_EQ(r.contiguous(), 2u);
  r.mark(4);
  EXPECT_EQ(r.contiguous(), 2u) << "after a restore only what arrives again counts";
}

}  // namespace
}  // namespace edge_slam
