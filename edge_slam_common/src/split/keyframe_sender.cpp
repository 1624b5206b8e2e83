#include "edge_slam/split/keyframe_sender.h"

#include <memory>

#include "edge_slam/util/log.h"

namespace edge_slam {

KeyFrameSender::KeyFrameSender(const DeliveryParams& params) : delivery_(params) {}

size_t KeyFrameSender::take_from(BoundedQueue<KeyFrameRecord>& outbox, std::chrono::milliseconds wait,
                                 double now) {
  size_t moved = 0;
  std::optional<KeyFrameRecord> record = wait.count() > 0 ? outbox.pop_for(wait) : outbox.try_pop();
  for (; record; record = outbox.try_pop()) {
    ++moved;
    if (!delivery_.add(std::make_shared<const KeyFrameRecord>(std::move(*record))) && full_warning_.allow(now))
      log_warn("KeyFrame resend queue full: the oldest unacknowledged record was dropped");
  }
  return moved;
}

KeyFrameSender::Due KeyFrameSender::due(double now, bool edge_listening) {
  Due d;
  if (!edge_listening) return d;
  d.records = delivery_.take_due(now);
  std::lock_guard<std::mutex> lock(floor_mutex_);
  if (now - last_floor_ >= kFloorPeriod) {
    d.floor = delivery_.floor();
    last_floor_ = now;
  }
  return d;
}

bool KeyFrameSender::on_ack(const KeyFrameAck& ack, double now) {
  const uint64_t restarts = delivery_.counters().edge_restarts;
  delivery_.on_ack(ack, now);
  return delivery_.counters().edge_restarts != restarts;
}

}  // namespace edge_slam
