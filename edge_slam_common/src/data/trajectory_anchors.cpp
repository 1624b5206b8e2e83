#include "edge_slam/data/trajectory_anchors.h"

namespace edge_slam {

void TrajectoryComposer::set_keyframe_pose(uint32_t id, const Eigen::Isometry3d& T_wk) {
  final_[id] = T_wk;
  resolved_.clear();
}

void TrajectoryComposer::set_parent_link(const KeyFrameLink& link) {
  links_[link.id] = link;
  resolved_.clear();
}

std::optional<Eigen::Isometry3d> TrajectoryComposer::keyframe_pose(uint32_t id) const {
  // Walk up to the first KeyFrame whose pose is known, then set the poses on the way back down.
  std::vector<const KeyFrameLink*> chain;
  std::optional<Eigen::Isometry3d> pose;
  for (uint32_t at = id;;) {
    if (const auto f = final_.find(at); f != final_.end()) {
      pose = f->second;
      break;
    }
    if (const auto r = resolved_.find(at); r != resolved_.end()) {
      pose = r->second;
      break;
    }
    const auto l = links_.find(at);
    if (l == links_.end() || chain.size() > links_.size()) break;  // no way up, or a cycle
    chain.push_back(&l->second);
    at = l->second.parent_id;
  }
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    if (pose) pose = *pose * (*it)->T_parent_kf;
    resolved_[(*it)->id] = pose;
  }
  return pose;
}

ComposedTrajectory TrajectoryComposer::compose(const std::vector<FrameAnchor>& frames) const {
  ComposedTrajectory out;
  out.poses.reserve(frames.size());
  for (const FrameAnchor& f : frames) {
    const std::optional<Eigen::Isometry3d> T_wr = keyframe_pose(f.reference_id);
    if (!T_wr) {
      ++out.unanchored;
      continue;
    }
    out.poses.emplace_back(f.stamp, *T_wr * f.T_ref_c);
  }
  return out;
}

TrajectoryComposer split_composer(const MobileAnchors& mobile, const EdgeKeyFrames& edge) {
  TrajectoryComposer c;
  for (const KeyFrameLink& link : mobile.keyframes) c.set_parent_link(link);
  for (const KeyFrameLink& link : edge.culled) c.set_parent_link(link);
  for (const KeyFramePose& kf : edge.in_map) c.set_keyframe_pose(kf.id, kf.T_wc);
  return c;
}

}  // namespace edge_slam
