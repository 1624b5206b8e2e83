#include "edge_slam/module/full_ba_update.h"

#include <deque>
#include <unordered_map>

namespace edge_slam {

int apply_full_ba_result(Map& map, const BundleAdjustmentResult& result) {
  if (!result.ok) return 0;
  const auto kfs = map.keyframes();
  std::unordered_map<uint32_t, Eigen::Isometry3d> old_pose, new_pose;
  for (const auto& kf : kfs) old_pose[kf->id()] = kf->T_cw();
  for (const auto& b : result.keyframes)
    if (old_pose.count(b.id)) new_pose[b.id] = b.T_cw;

  // Breadth-first down the spanning tree from every adjusted keyframe.
  std::deque<uint32_t> todo;
  for (const auto& [id, T] : new_pose) todo.push_back(id);
  int propagated = 0;
  while (!todo.empty()) {
    const uint32_t parent_id = todo.front();
    todo.pop_front();
    const auto parent = map.keyframe(parent_id);
    if (!parent) continue;
    for (uint32_t child_id : parent->children()) {
      if (new_pose.count(child_id) || !old_pose.count(child_id)) continue;
      const Eigen::Isometry3d T_child_parent = old_pose[child_id] * old_pose[parent_id].inverse();
      new_pose[child_id] = T_child_parent * new_pose[parent_id];
      todo.push_back(child_id);
      ++propagated;
    }
  }
  for (const auto& kf : kfs) {
    const auto it = new_pose.find(kf->id());
    if (it != new_pose.end() && !kf->is_bad()) kf->set_pose(it->second);
  }

  std::unordered_map<uint32_t, Eigen::Vector3d> adjusted;
  for (const auto& b : result.points) adjusted[b.id] = b.position;
  for (const auto& mp : map.map_points()) {
    if (mp->is_bad()) continue;
    const auto it = adjusted.find(mp->id());
    if (it != adjusted.end()) {
      if (!it->second.allFinite()) continue;
      mp->set_position(it->second);
    } else {
      // Not in the problem: follows its reference KeyFrame if that moved (another robot's map: not).
      const uint32_t ref = mp->reference_kf_id();
      if (!old_pose.count(ref) || !new_pose.count(ref)) continue;
      mp->set_position(new_pose[ref].inverse() * (old_pose[ref] * mp->position()));
    }
    mp->update_normal_and_depth(map);
  }
  return propagated;
}

}  // namespace edge_slam
