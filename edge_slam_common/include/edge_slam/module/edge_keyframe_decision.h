// The edge's KeyFrame conditions 1-2 (paper 4.4), as one pure function of the edge's state, the
// record and the time, so the rule is tested without threads or clocks. The predicates are the
// tracker's own (keyframe_decision.h), fed with what the mobile's decision saw (the record's
// counts): condition 2's weak-tracking clause lets a KeyFrame past a busy Local-Mapping, as in
// ORB-SLAM2. Condition 2 paces live KeyFrames only: one created more than late_keyframe_age
// seconds before it arrives is backlog (a link outage, an edge restart) and is taken.
#pragma once
#include <cstdint>

#include "edge_slam/io/wire_records.h"
#include "edge_slam/module/keyframe_decision.h"

namespace edge_slam {

struct EdgeKeyFrameState {
  bool any_inserted = false;               // since the last reset
  uint64_t last_inserted_frame_id = 0;
  bool relocalization_sent = false;        // the edge answered a relocalization request ...
  uint64_t last_relocalization_frame_id = 0;  // ... for this frame
  bool mapper_idle = true;                 // Local-Mapping has nothing queued or running
};

enum class EdgeKeyFrameDecision { kInsert, kInsertLate, kRejectCondition1, kRejectCondition2 };

// late_keyframe_age 0: every KeyFrame is paced (the paper). `now` and record.created_wall are
// wall-clock seconds (mobile and edge clocks synchronised).
EdgeKeyFrameDecision decide_edge_keyframe(const KeyFrameDecisionParams& params, double late_keyframe_age,
                                          const EdgeKeyFrameState& state, const KeyFrameRecord& record,
                                          double now);

// The decision inputs the record carries, in the tracker's terms.
KeyFrameDecisionInput edge_decision_input(const EdgeKeyFrameState& state, const KeyFrameRecord& record);

}  // namespace edge_slam
