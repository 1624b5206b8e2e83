#include "edge_slam/module/keyframe_delivery.h"

#include <algorithm>
#include <stdexcept>

#include "edge_slam/io/config_file.h"

namespace edge_slam {

DeliveryParams load_delivery_params(const ConfigMap& cfg) {
  DeliveryParams p;
  p.capacity = static_cast<size_t>(cfg.get_int_or("delivery/resend_capacity", 2000, 1, 100000));
  p.resend_timeout = cfg.get_double_or("delivery/resend_timeout", 1.0, 0.05, 60.0);
  p.resend_timeout_max = cfg.get_double_or("delivery/resend_timeout_max", 8.0, p.resend_timeout, 600.0);
  return p;
}

double load_checkpoint_period(const ConfigMap& cfg) {
  return cfg.get_double_or("delivery/checkpoint_period", 5.0, 0.5, 3600.0);
}

KeyFrameDelivery::KeyFrameDelivery(const DeliveryParams& params) : params_(params) {
  if (params_.capacity == 0) throw std::invalid_argument("KeyFrame delivery capacity must be >= 1");
  if (!(params_.resend_timeout > 0)) throw std::invalid_argument("KeyFrame resend timeout must be > 0");
  if (!(params_.resend_timeout_max >= params_.resend_timeout))
    throw std::invalid_argument("KeyFrame resend_timeout_max must be >= resend_timeout");
}

bool KeyFrameDelivery::add(RecordPtr record) {
  std::lock_guard<std::mutex> lock(mutex_);
  bool kept_all = true;
  if (entries_.size() >= params_.capacity) {
    entries_.pop_front();  // the oldest: the edge has had the longest to take it
    ++counters_.dropped_by_bound;
    kept_all = false;
  }
  highest_added_ = std::max(highest_added_, record->seq);
  Entry e;
  e.record = std::move(record);
  entries_.push_back(std::move(e));
  ++counters_.added;
  return kept_all;
}

std::vector<KeyFrameDelivery::RecordPtr> KeyFrameDelivery::take_due(double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<RecordPtr> due;
  for (Entry& e : entries_) {
    if (e.acked || (e.last_sent >= 0 && now - e.last_sent < e.wait)) continue;
    ++(e.sends == 0 ? counters_.sent : counters_.resent);
    ++e.sends;
    e.wait = e.last_sent < 0 ? params_.resend_timeout : std::min(2 * e.wait, params_.resend_timeout_max);
    e.last_sent = now;
    due.push_back(e.record);
  }
  return due;
}

void KeyFrameDelivery::free_through(uint64_t seq) {
  while (!entries_.empty() && entries_.front().record->seq <= seq) {
    if (!entries_.front().ever_acked) ++counters_.acknowledged;  // durable implies received
    entries_.pop_front();
    ++counters_.durable;
  }
}

void KeyFrameDelivery::on_ack(const KeyFrameAck& ack, double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++counters_.acks;
  // The first acknowledgement after a silence: the link is back, what it lacks goes now.
  const bool link_back = last_ack_time_ >= 0 && now - last_ack_time_ > params_.resend_timeout;
  last_ack_time_ = now;
  const bool restarted = have_boot_ && ack.boot_id != boot_id_;
  if (restarted) ++counters_.edge_restarts;
  // Within one boot the edge's contiguous seq only grows: a late, older ack changes nothing.
  received_seq_ = (restarted || !have_boot_) ? ack.received_seq : std::max(received_seq_, ack.received_seq);
  have_boot_ = true;
  boot_id_ = ack.boot_id;
  for (Entry& e : entries_) {
    const bool received = e.record->seq <= received_seq_;
    if (received && !e.ever_acked) {
      e.ever_acked = true;
      ++counters_.acknowledged;
    }
    // A restarted edge kept only its checkpoint: what it had beyond goes again, at once.
    if (!received && (e.acked || restarted || link_back)) e.last_sent = -1;
    e.acked = received;
  }
  free_through(ack.persistent ? std::min(ack.durable_seq, received_seq_) : received_seq_);
}

uint64_t KeyFrameDelivery::floor() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.empty() ? highest_added_ : entries_.front().record->seq - 1;
}

double KeyFrameDelivery::seconds_since_ack(double now) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_ack_time_ < 0 ? -1.0 : now - last_ack_time_;
}

DeliveryCounters KeyFrameDelivery::counters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  DeliveryCounters c = counters_;
  c.queued = entries_.size();
  return c;
}

}  // namespace edge_slam
