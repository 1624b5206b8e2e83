#include "edge_slam/module/edge_keyframe_decision.h"

namespace edge_slam {

KeyFrameDecisionInput edge_decision_input(const EdgeKeyFrameState& state, const KeyFrameRecord& r) {
  KeyFrameDecisionInput in;
  in.frame_id = r.frame_id;
  // Condition 1 counts from a relocalization the edge assisted; a KeyFrame made before it is not affected.
  in.relocalized_before = state.relocalization_sent && r.frame_id >= state.last_relocalization_frame_id;
  in.last_relocalization_frame_id = state.last_relocalization_frame_id;
  in.last_keyframe_frame_id = state.last_inserted_frame_id;
  in.mapper_idle = !state.any_inserted || state.mapper_idle;
  in.tracked_points = r.tracked_points;
  in.reference_tracked_points = r.reference_points;
  in.tracked_close_points = r.tracked_close_points;
  in.untracked_close_points = r.untracked_close_points;
  return in;
}

EdgeKeyFrameDecision decide_edge_keyframe(const KeyFrameDecisionParams& params, double late_keyframe_age,
                                          const EdgeKeyFrameState& state, const KeyFrameRecord& r, double now) {
  const KeyFrameDecisionInput in = edge_decision_input(state, r);
  if (!relocalization_gap_passed(params, in)) return EdgeKeyFrameDecision::kRejectCondition1;
  const bool late = late_keyframe_age > 0 && r.created_wall > 0 && now - r.created_wall > late_keyframe_age;
  if (late) return EdgeKeyFrameDecision::kInsertLate;
  return keyframe_gap_or_mapper_idle(params, in) ? EdgeKeyFrameDecision::kInsert
                                                 : EdgeKeyFrameDecision::kRejectCondition2;
}

}  // namespace edge_slam
