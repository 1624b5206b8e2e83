// How a trajectory is kept while the map still moves (ORB-SLAM2's way of saving one): a tracked
// frame is anchored on its reference KeyFrame (T_ref_c), a KeyFrame on its spanning-tree parent
// (T_parent_kf). Once the map is final (loops closed, BA done), each frame's pose is its
// reference KeyFrame's final pose times its anchor, so every correction reaches every frame.
// A KeyFrame that is no longer in the map (culled by Local-Mapping, or refused by the edge and
// never in it) is reached through its parent links; a frame whose chain never reaches a KeyFrame
// with a final pose is counted, not invented.
// One composer for the monolithic system (SlamSystem::trajectory) and the split (the mobile's
// anchors + the edge's final KeyFrames, tools/compose_trajectory).
#pragma once
#include <Eigen/Geometry>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "edge_slam/util/ids.h"

namespace edge_slam {

struct FrameAnchor {
  double stamp = 0;
  uint32_t reference_id = kNoId;
  Eigen::Isometry3d T_ref_c = Eigen::Isometry3d::Identity();  // frame pose in its reference KeyFrame
};

struct KeyFrameLink {
  uint32_t id = kNoId;
  uint32_t parent_id = kNoId;
  Eigen::Isometry3d T_parent_kf = Eigen::Isometry3d::Identity();  // KeyFrame pose in its parent
};

// A KeyFrame's pose in a map that holds it.
struct KeyFramePose {
  uint32_t id = kNoId;
  double stamp = 0;
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
};

// What the mobile tracked (its frames on their reference KeyFrames, its KeyFrames on their
// parents) and what the edge's Global-Map holds in the end (its KeyFrames' final poses, and the
// KeyFrames Local-Mapping culled, on the parent each had then).
struct MobileAnchors {
  std::vector<FrameAnchor> frames;
  std::vector<KeyFrameLink> keyframes;
};
struct EdgeKeyFrames {
  std::vector<KeyFramePose> in_map;
  std::vector<KeyFrameLink> culled;
};

struct ComposedTrajectory {
  std::vector<std::pair<double, Eigen::Isometry3d>> poses;  // (stamp, T_wc), in the frames' order
  size_t unanchored = 0;  // frames whose KeyFrame chain reaches no final pose (left out)
};

class TrajectoryComposer {
 public:
  // A KeyFrame's final pose (T_wc); it wins over any link of the same KeyFrame.
  void set_keyframe_pose(uint32_t id, const Eigen::Isometry3d& T_wk);
  // A later link of the same KeyFrame replaces an earlier one: give what the tracker knew first
  // and the map's own relation at culling time last, since that is the map's final word.
  void set_parent_link(const KeyFrameLink& link);

  // The KeyFrame's final pose, through its parent links if needed; nullopt when the chain ends
  // without one (or loops back on itself).
  std::optional<Eigen::Isometry3d> keyframe_pose(uint32_t id) const;
  ComposedTrajectory compose(const std::vector<FrameAnchor>& frames) const;

 private:
  std::unordered_map<uint32_t, Eigen::Isometry3d> final_;
  std::unordered_map<uint32_t, KeyFrameLink> links_;
  // Chains are walked once: a KeyFrame reached through links is remembered (or its absence).
  mutable std::unordered_map<uint32_t, std::optional<Eigen::Isometry3d>> resolved_;
};

// The split's composer: the mobile's links, then the edge's culled links (they replace the
// mobile's for the same KeyFrame: the edge may have re-parented it), then the Global-Map poses.
TrajectoryComposer split_composer(const MobileAnchors& mobile, const EdgeKeyFrames& edge);

}  // namespace edge_slam
