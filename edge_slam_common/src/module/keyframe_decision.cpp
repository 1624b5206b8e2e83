#include "edge_slam/module/keyframe_decision.h"

namespace edge_slam {

bool relocalization_gap_passed(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  if (!in.relocalized_before) return true;
  return in.frame_id >= in.last_relocalization_frame_id + static_cast<uint64_t>(p.min_frames_after_relocalization);
}

bool weak_tracking(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_points < p.weak_ratio * in.reference_tracked_points || needs_close_points(p, in);
}

bool keyframe_gap_or_mapper_idle(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.mapper_idle || weak_tracking(p, in) ||
         in.frame_id >= in.last_keyframe_frame_id + static_cast<uint64_t>(p.max_frames_between_keyframes);
}

bool tracks_enough_points(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_points + in.depth_point_inliers >= p.min_tracked_points;
}

bool tracks_fewer_than_reference(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_points < p.ref_ratio * in.reference_tracked_points;
}

bool needs_close_points(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  return in.tracked_close_points < p.close_points_tracked &&
         in.untracked_close_points > p.close_points_new;
}

uint32_t keyframe_condition_bits(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in) {
  uint32_t bits = 0;
  if (relocalization_gap_passed(p, in)) bits |= kCondRelocalizationGap;
  if (keyframe_gap_or_mapper_idle(p, in)) bits |= kCondGapOrMapperIdle;
  if (tracks_enough_points(p, in)) bits |= kCondEnoughPoints;
  if (tracks_fewer_than_reference(p, in)) bits |= kCondFewerThanReference;
  if (needs_close_points(p, in)) bits |= kCondNeedsClosePoints;
  if (weak_tracking(p, in)) bits |= kCondWeakTracking;
  return bits;
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
