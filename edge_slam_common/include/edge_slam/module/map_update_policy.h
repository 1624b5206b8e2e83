// The mobile's Local-Map update acceptance rules (paper 4.4 and 4.7.1). A periodic update is
// applied only if (a) the controller allows updates, (b) tracking is initialised, (c) a
// KeyFrame was created since the last applied update, and (d) more than
// TC = ITC / ((KFN / LMU) + 1) seconds (eq. 1) have passed since the last KeyFrame was created.
// A relocalization update, while tracking is lost, lifts the time and size limits (4.7.5).
// Every decision is counted per rule so the controller GUI and tests can see why.
#pragma once
#include <edge_slam/io/wire_records.h>

#include <cstdint>
#include <string>

namespace edge_slam {

struct MapUpdatePolicyParams {
  double initial_time_constraint = 0.3;  // ITC, seconds
  int update_size = 6;                   // LMU, KeyFrames per update
};

enum class UpdateDecision {
  kAccept,
  kRejectController,    // (a)
  kRejectInitializing,  // (b)
  kRejectRedundant,     // (c)
  kRejectKeyFrameRate,  // (d)
  kRejectNotLost,       // a relocalization update that arrives after tracking recovered
  kDeferred,            // refused by (d) on arrival, re-checked on the next frames (MobileSession)
  kRejectInvalid,       // a record the rebuild refused (counted by count_invalid())
};

const char* to_string(UpdateDecision d);

// What the tracking side knows when an update arrives.
struct TrackingSnapshot {
  bool initialized = false;
  bool lost = false;
  bool keyframe_since_last_update = false;
  double now = 0;                 // seconds
  double last_keyframe_time = 0;  // seconds; creation time of the newest KeyFrame
  int local_map_keyframes = 0;    // KFN
};

struct MapUpdateCounters {
  uint32_t received = 0, accepted = 0, relocalization_applied = 0;
  uint32_t rejected_controller = 0, rejected_initializing = 0, rejected_redundant = 0;
  uint32_t rejected_keyframe_rate = 0, rejected_not_lost = 0, rejected_invalid = 0;
};

class MapUpdatePolicy {
 public:
  explicit MapUpdatePolicy(const MapUpdatePolicyParams& params = {});

  // Eq. 1: the minimum quiet time after the last KeyFrame before an update may be applied.
  double time_constraint(int local_map_keyframes) const;

  // Decides and counts. Thread-compatible: the caller serialises calls.
  UpdateDecision decide(MapUpdateKind kind, const TrackingSnapshot& s);
  // The two halves of decide(), for an update whose final decision comes later (deferred).
  UpdateDecision evaluate(MapUpdateKind kind, const TrackingSnapshot& s) const;
  void count(MapUpdateKind kind, UpdateDecision d);
  void count_invalid() { ++counters_.received; ++counters_.rejected_invalid; }

  void set_enabled(bool enabled) { enabled_ = enabled; }
  bool enabled() const { return enabled_; }
  const MapUpdateCounters& counters() const { return counters_; }
  const MapUpdatePolicyParams& params() const { return params_; }

 private:
  MapUpdatePolicyParams params_;
  bool enabled_ = true;
  MapUpdateCounters counters_;
};

}  // namespace edge_slam
