#include "edge_slam/module/update_carry_over.h"

#include <unordered_set>

namespace edge_slam {

Eigen::Isometry3d map_correction_at(const Map& new_map, const Map& old_map, uint32_t anchor_id) {
  const auto now = new_map.keyframe(anchor_id);
  const auto before = old_map.keyframe(anchor_id);
  if (!now || !before) return Eigen::Isometry3d::Identity();
  return now->T_wc() * before->T_cw();
}

namespace {

// The KeyFrame whose correction a carried one follows: its parent when the update holds it,
// else the updated KeyFrame it shares most points with; kNoId when it has none.
uint32_t anchor_of(const KeyFrame& kf, const Map& new_map) {
  if (kf.parent_id() != kNoId && new_map.keyframe(kf.parent_id())) return kf.parent_id();
  uint32_t best = kNoId;
  int best_w = 0;
  for (const auto& [id, w] : kf.connection_weights())
    if (w > best_w && new_map.keyframe(id)) {
      best = id;
      best_w = w;
    }
  return best;
}

}  // namespace

CarryOverResult carry_over_keyframes(Map& new_map, const Map& old_map, const std::vector<uint32_t>& ids,
                                     KeyFrameDatabase* database, uint32_t fallback_anchor) {
  CarryOverResult out;
  const Eigen::Isometry3d fallback = map_correction_at(new_map, old_map, fallback_anchor);
  std::unordered_map<uint32_t, Eigen::Isometry3d> correction_of;  // carried KeyFrame -> its correction
  for (uint32_t id : ids) {
    const auto kf = old_map.keyframe(id);
    if (!kf || kf->is_bad() || new_map.keyframe(id)) continue;
    // A carried parent has already been corrected: follow it; otherwise an updated neighbour.
    Eigen::Isometry3d C = fallback;
    if (const auto it = correction_of.find(kf->parent_id()); it != correction_of.end()) {
      C = it->second;
    } else {
      const uint32_t anchor = anchor_of(*kf, new_map);
      if (anchor != kNoId) C = map_correction_at(new_map, old_map, anchor);
    }
    correction_of[id] = C;
    kf->set_pose((C * kf->T_wc()).inverse());
    // Its links are re-derived from the new map below; a parent the update dropped is re-chosen.
    kf->clear_connections();
    if (kf->parent_id() != kNoId && !new_map.keyframe(kf->parent_id()) && !correction_of.count(kf->parent_id()))
      kf->set_parent(kNoId);
    new_map.add_keyframe(kf);
    const auto point_ids = kf->map_point_ids();
    for (size_t i = 0; i < point_ids.size(); ++i) {
      if (point_ids[i] == kNoId) continue;
      if (const auto edge_version = new_map.map_point(point_ids[i])) {
        if (edge_version->index_in(id) < 0) edge_version->add_observation(id, static_cast<int>(i));
        ++out.points_linked;
        continue;
      }
      const auto mp = old_map.map_point(point_ids[i]);
      if (!mp || mp->is_bad()) {
        kf->erase_map_point_id(i);
        continue;
      }
      mp->set_position(C * mp->position());
      new_map.add_map_point(mp);
      ++out.points_carried;
    }
    ++out.keyframes;
  }
  // Links once everything is in: normals, covisibility and the spanning tree see the new map.
  for (uint32_t id : ids) {
    const auto kf = new_map.keyframe(id);
    if (!kf || !correction_of.count(id)) continue;
    for (const auto& mp : kf->map_points(new_map))
      if (mp && mp->reference_kf_id() == id) mp->update_normal_and_depth(new_map);
    kf->update_connections(new_map);
    if (database && kf->has_bow()) database->add(kf);
  }
  return out;
}

}  // namespace edge_slam
