#include "edge_slam/module/keyframe_decision.h"

namespace edge_slam {

bool relocalization_gap_passed(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  if (!in.relocalized_before) return true;
  return in.frame_id >= in.last_relocalization_frame_id + static_cast<uint64_t>(p.min_frames_after_relocalization);
}

bool keyframe_gap_or_mapper_idle(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  const bool weak_tracking = in.tracked_points < p.weak_ratio * in.reference_tracked_points ||
                             needs_close_points(p, in);
  return in.mapper_idle || weak_tracking ||
         in.frame_id >= in.last_keyframe_frame_id + static_cast<uint64_t>(p.max_frames_between_keyframes);
}

bool tracks_enough_points(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_points >= p.min_tracked_points;
}

bool tracks_fewer_than_reference(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_points < p.ref_ratio * in.reference_tracked_points;
}

bool needs_close_points(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_close_points < p.close_points_tracked &&
         in.untracked_close_points > p.close_points_new;
}

bool edge_conditions_hold(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return relocalization_gap_passed(p, in) && keyframe_gap_or_mapper_idle(p, in);
}

bool mobile_conditions_hold(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return tracks_enough_points(p, in) &&
         (tracks_fewer_than_reference(p, in) || needs_close_points(p, in));
}

bool need_new_keyframe(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in,
                       KeyFrameConditionSet set) {
  switch (set) {
    case KeyFrameConditionSet::kEdge: return edge_conditions_hold(p, in);
    case KeyFrameConditionSet::kMobile: return mobile_conditions_hold(p, in);
    case KeyFrameConditionSet::kAll: break;
  }
  return edge_conditions_hold(p, in) && mobile_conditions_hold(p, in);
}

}  // namespace edge_slam
