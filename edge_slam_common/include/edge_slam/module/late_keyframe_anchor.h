#pragma once
// A KeyFrame the mobile made after the edge moved its map (a loop correction, a merge, a full
// BA) but before any update could tell the mobile: it is posed in the frame the mobile still
// had, so inserted as received it sits off by the correction. Found on the synthetic split:
// the edge closed the loop at 28.9 s, the KeyFrames of the last second came in uncorrected and
// that second of the final trajectory was 7 cm off. ORB-SLAM2 moves KeyFrames made during a
// correction with their parent; here the edge re-anchors such a KeyFrame on its parent's
// corrected pose, keeping the relative pose the mobile measured (as compose_trajectory does
// for frames). Only when the mobile's view of the parent is known exactly: the parent came from
// the mobile and no update has been built for the robot since (an update changes the mobile's
// poses by rules the edge does not replay), and a correction has moved the map since.
#include <cstdint>
#include <optional>

#include <Eigen/Geometry>

namespace edge_slam {

// The pose of a KeyFrame as the mobile sent it (robot frame), with the edge's update and
// map-move counters at that moment.
struct MobileKeyFrameView {
  Eigen::Isometry3d T_cw_robot = Eigen::Isometry3d::Identity();
  uint64_t update_seq = 0;  // the robot's next update seq when it was received
  uint64_t map_moves = 0;   // the edge's count of corrections applied when it was received
};

// The parent's pose (T_cw) as the mobile had it, in the map's coordinates now, or nullopt when
// an update has been built for the robot since it was received (the mobile's poses then change
// by rules the edge does not replay, so its view is no longer known).
inline std::optional<Eigen::Isometry3d> mobile_pose_in_map(const MobileKeyFrameView& view,
                                                           const Eigen::Isometry3d& T_group_robot,
                                                           uint64_t update_seq_now) {
  if (view.update_seq != update_seq_now) return std::nullopt;
  return view.T_cw_robot * T_group_robot.inverse();
}

// How far (camera centre, m) a KeyFrame the edge now has at T_wc_now is from where the mobile
// has it, or nullopt when the mobile's view is no longer known (as mobile_pose_in_map).
inline std::optional<double> distance_from_mobile_view(const MobileKeyFrameView& view,
                                                       const Eigen::Isometry3d& T_group_robot,
                                                       uint64_t update_seq_now, const Eigen::Isometry3d& T_wc_now) {
  const auto T_cw_mobile = mobile_pose_in_map(view, T_group_robot, update_seq_now);
  if (!T_cw_mobile) return std::nullopt;
  return (T_wc_now.translation() - T_cw_mobile->inverse().translation()).norm();
}

// The world -> world motion M (X' = M X; a pose T_cw becomes T_cw M^-1) that carries a new
// KeyFrame and its new points from the mobile's uncorrected view onto its parent's corrected
// pose, or nullopt when nothing is to be done or the mobile's view is not known.
//   parent_view: the parent as received; T_group_robot: the robot's frame in the map's
//   coordinates now; T_cw_parent_now: the parent's pose in the Global-Map now.
inline std::optional<Eigen::Isometry3d> late_keyframe_correction(const MobileKeyFrameView& parent_view,
                                                                 const Eigen::Isometry3d& T_group_robot,
                                                                 const Eigen::Isometry3d& T_cw_parent_now,
                                                                 uint64_t update_seq_now, uint64_t map_moves_now) {
  if (parent_view.map_moves == map_moves_now) return std::nullopt;
  // The mobile's parent pose in the map's coordinates, converted as the new KeyFrame is.
  const auto T_cw_parent_then = mobile_pose_in_map(parent_view, T_group_robot, update_seq_now);
  if (!T_cw_parent_then) return std::nullopt;
  return T_cw_parent_now.inverse() * *T_cw_parent_then;
}

}  // namespace edge_slam
