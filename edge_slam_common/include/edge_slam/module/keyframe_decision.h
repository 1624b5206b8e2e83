// The five keyframe conditions of ORB-SLAM2 (Edge-SLAM paper, section 4.1), each a
// separate predicate so that the split system can evaluate 1-2 on the edge (where the
// mapper's state is known) and 3-5 on the mobile (where the tracking statistics are).
//   (1) at least N frames have passed since the last relocalization;
//   (2) at least M frames since the last keyframe, or the local mapper is idle, or (ORB-SLAM2
//       RGB-D, c1c) tracking is weak: fewer than weak_ratio x the reference keyframe's points
//       or close points needed as in (5) - then a busy mapper gets the keyframe anyway (its
//       local BA is aborted), which is what lets tracking survive a fast turn;
//   (3) the frame tracks at least K points;
//   (4) it tracks fewer than ref_ratio x the points of its reference keyframe;
//   (5) it tracks fewer than C close points and could create more than D new close ones.
// As in ORB-SLAM2, (4) and (5) are alternatives: a keyframe is wanted when
// (1) and (2) and (3) and ((4) or (5)).
#pragma once
#include <cstdint>

namespace edge_slam {

struct KeyFrameDecisionParams {
  int min_frames_after_relocalization = 20;  // (1) paper/ORB-SLAM2: 20 (= fps)
  int max_frames_between_keyframes = 20;     // (2) paper: 20, ORB-SLAM2: fps
  int min_tracked_points = 50;               // (3) paper: 50
  double ref_ratio = 0.9;                    // (4) paper: 0.9 (ORB-SLAM2 RGB-D code: 0.75)
  int close_points_tracked = 100;            // (5) ORB-SLAM2: 100
  int close_points_new = 70;                 // (5) ORB-SLAM2: 70
  double weak_ratio = 0.25;                  // (2) ORB-SLAM2 RGB-D c1c: 0.25
};

struct KeyFrameDecisionInput {
  uint64_t frame_id = 0;
  bool relocalized_before = false;          // has a relocalization ever happened
  uint64_t last_relocalization_frame_id = 0;
  uint64_t last_keyframe_frame_id = 0;
  bool mapper_idle = true;
  int tracked_points = 0;                    // inliers matched to map points
  int reference_tracked_points = 0;          // good points of the reference keyframe
  int tracked_close_points = 0;              // inliers with close depth
  int untracked_close_points = 0;            // close-depth keypoints without a map point
  // Inliers to the last frame's depth points (tracking/last_frame_depth_points; 0 when off).
  // Condition (3) asks whether the pose is well supported, and these support it: in a fast turn
  // away from the map the map inliers fall under 50 a frame after the pose stopped needing them,
  // and the frame that must become a KeyFrame could not (synthetic look-away turn, 2026-12-05).
  int depth_point_inliers = 0;
};

// Which conditions the tracking module evaluates itself.
enum class KeyFrameConditionSet {
  kAll,     // monolithic: 1-5
  kMobile,  // split, mobile side: 3-5 (1-2 are checked by the edge's local mapping)
  kEdge,    // split, edge side: 1-2
};

bool relocalization_gap_passed(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);  // (1)
bool keyframe_gap_or_mapper_idle(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);  // (2)
bool tracks_enough_points(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);  // (3)
bool tracks_fewer_than_reference(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);  // (4)
bool needs_close_points(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);  // (5)

// Which of the predicates above held, as bits (per-frame logs, KeyFrame statistics).
enum KeyFrameConditionBits : uint32_t {
  kCondRelocalizationGap = 1u << 0,  // (1)
  kCondGapOrMapperIdle = 1u << 1,    // (2)
  kCondEnoughPoints = 1u << 2,       // (3)
  kCondFewerThanReference = 1u << 3, // (4)
  kCondNeedsClosePoints = 1u << 4,   // (5)
  kCondWeakTracking = 1u << 5,       // (2)'s weak-tracking clause alone
};
uint32_t keyframe_condition_bits(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);
bool weak_tracking(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);

bool edge_conditions_hold(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);    // 1 and 2
bool mobile_conditions_hold(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in);  // 3 and (4 or 5)
bool need_new_keyframe(const KeyFrameDecisionParams& p, const KeyFrameDecisionInput& in,
                       KeyFrameConditionSet set);

}  // namespace edge_slam
