// Test helper: the KeyFrame records and acknowledgements of the delivery tests (only the seq
// and id matter to the protocol).
#pragma once
#include "edge_slam/module/keyframe_delivery.h"

namespace edge_slam {
namespace test_support {

inline KeyFrameRecord delivery_record(uint64_t seq) {
  KeyFrameRecord r;
  r.seq = seq;
  r.id = static_cast<uint32_t>(100 + seq);
  return r;
}

inline KeyFrameAck delivery_ack(uint64_t boot, uint64_t received, uint64_t durable, bool persistent = true) {
  KeyFrameAck a;
  a.boot_id = boot;
  a.received_seq = received;
  a.durable_seq = durable;
  a.persistent = persistent;
  return a;
}

}  // namespace test_support
}  // namespace edge_slam
