#include <edge_slam/module/map_update_policy.h>

#include <stdexcept>

namespace edge_slam {

const char* to_string(UpdateDecision d) {
  switch (d) {
    case UpdateDecision::kAccept: return "accepted";
    case UpdateDecision::kRejectController: return "controller";
    case UpdateDecision::kRejectInitializing: return "initializing";
    case UpdateDecision::kRejectRedundant: return "redundant";
    case UpdateDecision::kRejectKeyFrameRate: return "keyframe_rate";
    case UpdateDecision::kRejectNotLost: return "not_lost";
    case UpdateDecision::kDeferred: return "deferred";
    case UpdateDecision::kRejectInvalid: return "invalid";
  }
  return "unknown";
}

MapUpdatePolicy::MapUpdatePolicy(const MapUpdatePolicyParams& params) : params_(params) {
  if (!(params_.initial_time_constraint >= 0))
    throw std::invalid_argument("initial_time_constraint must be >= 0 seconds");
  if (params_.update_size < 1) throw std::invalid_argument("update_size must be >= 1 KeyFrame");
}

double MapUpdatePolicy::time_constraint(int kfn) const {
  return params_.initial_time_constraint /
         (static_cast<double>(kfn) / static_cast<double>(params_.update_size) + 1.0);
}

UpdateDecision MapUpdatePolicy::decide(MapUpdateKind kind, const TrackingSnapshot& s) {
  const UpdateDecision d = evaluate(kind, s);
  count(kind, d);
  return d;
}

UpdateDecision MapUpdatePolicy::evaluate(MapUpdateKind kind, const TrackingSnapshot& s) const {
  UpdateDecision d = UpdateDecision::kAccept;
  // The controller is the user's/planner's explicit intent: it gates every kind of update.
  if (!enabled_) {
    d = UpdateDecision::kRejectController;
  } else if (kind == MapUpdateKind::kRelocalization) {
    // Relocalization is a priority over performance: no time or size limit, but only useful
    // while lost (a late answer would replace a healthy Local-Map with candidates).
    d = s.lost ? UpdateDecision::kAccept : UpdateDecision::kRejectNotLost;
  } else if (!s.initialized) {
    d = UpdateDecision::kRejectInitializing;
  } else if (!s.keyframe_since_last_update) {
    d = UpdateDecision::kRejectRedundant;
  } else if (s.now - s.last_keyframe_time <= time_constraint(s.local_map_keyframes)) {
    d = UpdateDecision::kRejectKeyFrameRate;
  }
  return d;
}

void MapUpdatePolicy::count(MapUpdateKind kind, UpdateDecision d) {
  if (d == UpdateDecision::kDeferred) return;  // counted once its final decision is made
  ++counters_.received;
  switch (d) {
    case UpdateDecision::kAccept:
      ++counters_.accepted;
      if (kind == MapUpdateKind::kRelocalization) ++counters_.relocalization_applied;
      break;
    case UpdateDecision::kRejectController: ++counters_.rejected_controller; break;
    case UpdateDecision::kRejectInitializing: ++counters_.rejected_initializing; break;
    case UpdateDecision::kRejectRedundant: ++counters_.rejected_redundant; break;
    case UpdateDecision::kRejectKeyFrameRate: ++counters_.rejected_keyframe_rate; break;
    case UpdateDecision::kRejectNotLost: ++counters_.rejected_not_lost; break;
    case UpdateDecision::kDeferred: break;
    case UpdateDecision::kRejectInvalid: ++counters_.rejected_invalid; break;
  }
}

}  // namespace edge_slam
