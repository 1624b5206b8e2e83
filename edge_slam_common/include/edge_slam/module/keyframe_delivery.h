// Mobile side of KeyFrame delivery (issue #7): every KeyFrame record the mobile makes reaches
// the edge exactly once across edge restarts and link outages. Sent records stay here until the
// edge acknowledges them; unacknowledged ones are resent after `resend_timeout`, oldest first.
// The edge's KeyFrameAck says which seqs it holds: all of 1..received_seq, of which 1..durable_seq
// are in its last checkpoint. A record is freed once durable (or once received when the edge
// does not persist): an edge that restarts from its checkpoint (new boot id) may have lost what
// came after, and then everything after its durable seq is sent again. The edge de-duplicates.
// Bound: at `capacity` records the oldest is dropped (counted) so memory stays flat in a long
// outage; floor() tells the edge which seqs will never come, so its received_seq can pass them.
// Thread-safe (the sender thread adds and takes, the ack callback acknowledges).
#pragma once
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "edge_slam/io/wire_records.h"

namespace edge_slam {

struct KeyFrameAck {
  uint64_t boot_id = 0;       // changes whenever the edge's session restarts or loads a map
  uint64_t received_seq = 0;  // every seq <= this was received (or skipped past the floor)
  uint64_t durable_seq = 0;   // every seq <= this is in the edge's last checkpoint
  bool persistent = false;    // false: the edge keeps no checkpoint, durable_seq is meaningless
  uint64_t mapped_seq = 0;    // every seq <= this is through the edge's decision and Local-Mapping
  bool mapper_busy_elsewhere = false;  // several mobiles: Local-Mapping holds another robot's KeyFrame
};

struct DeliveryParams {
  size_t capacity = 2000;       // records held (sent, not yet durable); oldest dropped beyond
  double resend_timeout = 1.0;  // seconds without acknowledgement before a record is sent again
  // Each further resend of a record waits twice as long, up to this: through a long outage the
  // link is not flooded with copies (the first acknowledgement after it makes them due at once).
  double resend_timeout_max = 8.0;
};

class ConfigMap;
// The "delivery:" section of config/slam.yaml; throws naming the key and range on a bad value.
DeliveryParams load_delivery_params(const ConfigMap& cfg);
// delivery/checkpoint_period: seconds between the edge's checkpoints (split/edge_durability.h).
double load_checkpoint_period(const ConfigMap& cfg);

struct DeliveryCounters {
  uint64_t added = 0, sent = 0, resent = 0, acknowledged = 0, durable = 0, dropped_by_bound = 0;
  size_t queued = 0;
  uint64_t acks = 0, edge_restarts = 0;  // acks taken; boot id changes seen
};

class KeyFrameDelivery {
 public:
  using RecordPtr = std::shared_ptr<const KeyFrameRecord>;
  explicit KeyFrameDelivery(const DeliveryParams& params = {});

  // A new record (seq increasing); returns false when the bound dropped the oldest to make room.
  bool add(RecordPtr record);
  // The records to publish now, in seq order: never sent, or unacknowledged for resend_timeout.
  // They are counted as sent / resent here.
  std::vector<RecordPtr> take_due(double now);
  void on_ack(const KeyFrameAck& ack, double now);
  // Every seq <= floor is accounted for: freed after the edge had it, or dropped here.
  uint64_t floor() const;
  // Seconds since the last acknowledgement; negative before the first.
  double seconds_since_ack(double now) const;
  DeliveryCounters counters() const;

 private:
  struct Entry {
    RecordPtr record;
    double last_sent = -1;    // < 0: due at once (new, or lost by a restarted edge)
    uint32_t sends = 0;
    double wait = 0;          // before the next resend (doubles per resend, reset by a returning link)
    bool acked = false;       // in the edge's received range (this boot)
    bool ever_acked = false;  // counted as acknowledged once
  };
  void free_through(uint64_t seq);

  DeliveryParams params_;
  mutable std::mutex mutex_;
  std::deque<Entry> entries_;  // seq order
  uint64_t highest_added_ = 0, boot_id_ = 0, received_seq_ = 0;
  bool have_boot_ = false;
  double last_ack_time_ = -1;
  DeliveryCounters counters_;
};

}  // namespace edge_slam
