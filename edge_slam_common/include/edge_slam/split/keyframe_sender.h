// The mobile's KeyFrame sender: the protocol its sender thread runs (the thread and the
// publishing stay in the nodelet). Records move from the session's outbox, which tracking only
// ever pushes into so network trouble never stalls it, into the resend queue
// (module/keyframe_delivery.h); each step then says what to publish now: new records and those
// unacknowledged for too long, and every kFloorPeriod seconds the floor (seqs the edge will
// never get, module/keyframe_delivery.h). While nobody listens (edge down) nothing is due: the
// records wait, and the edge's next acknowledgement brings them out. Time is an argument.
// Thread-safe: the sender thread takes and steps, the ack callback acknowledges.
#pragma once
#include <chrono>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include "edge_slam/module/keyframe_delivery.h"
#include "edge_slam/util/bounded_queue.h"
#include "edge_slam/util/log_throttle.h"

namespace edge_slam {

class KeyFrameSender {
 public:
  static constexpr double kFloorPeriod = 0.2;  // seconds between floor messages

  explicit KeyFrameSender(const DeliveryParams& params = {});

  // Moves every record waiting in the outbox into the resend queue, waiting up to `wait` for the
  // first one (zero: only what is there). A record the bound pushes out is counted
  // (dropped_by_bound) and warned about, at most every 5 s. Returns the records moved.
  size_t take_from(BoundedQueue<KeyFrameRecord>& outbox, std::chrono::milliseconds wait, double now);

  struct Due {
    std::vector<KeyFrameDelivery::RecordPtr> records;  // publish in this order
    std::optional<uint64_t> floor;                     // publish on keyframe_floor when set
  };
  Due due(double now, bool edge_listening);

  // True when the acknowledgement shows an edge that restarted (new boot id): what came after
  // its durable seq is due again at once.
  bool on_ack(const KeyFrameAck& ack, double now);

  DeliveryCounters counters() const { return delivery_.counters(); }
  double seconds_since_ack(double now) const { return delivery_.seconds_since_ack(now); }

 private:
  KeyFrameDelivery delivery_;
  LogThrottle full_warning_{5.0};
  std::mutex floor_mutex_;
  double last_floor_ = -std::numeric_limits<double>::infinity();
};

}  // namespace edge_slam
