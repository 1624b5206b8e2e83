#include "edge_slam/data/map_edit.h"

#include <set>

#include "edge_slam/data/keyframe_database.h"

namespace edge_slam {

void erase_map_point(Map& map, const std::shared_ptr<MapPoint>& mp) {
  mp->set_bad();
  for (const auto& [kf_id, idx] : mp->observations()) {
    const auto kf = map.keyframe(kf_id);
    if (kf && kf->map_point_id(idx) == mp->id()) kf->erase_map_point_id(idx);
  }
  mp->clear_observations();
  map.erase_map_point(mp->id());
}

void add_observation(const std::shared_ptr<KeyFrame>& kf, size_t index, const std::shared_ptr<MapPoint>& mp) {
  kf->set_map_point_id(index, mp->id());
  mp->add_observation(kf->id(), static_cast<int>(index));
}

void erase_observation(Map& map, const std::shared_ptr<KeyFrame>& kf, const std::shared_ptr<MapPoint>& mp) {
  const int idx = mp->index_in(kf->id());
  if (idx >= 0 && kf->map_point_id(idx) == mp->id()) kf->erase_map_point_id(idx);
  mp->erase_observation(kf->id());
  if (mp->num_observations() == 0) erase_map_point(map, mp);
}

void replace_map_point(Map& map, const std::shared_ptr<MapPoint>& old_mp, const std::shared_ptr<MapPoint>& by) {
  if (old_mp == by || old_mp->id() == by->id()) return;
  for (const auto& [kf_id, idx] : old_mp->observations()) {
    const auto kf = map.keyframe(kf_id);
    if (!kf) continue;
    if (by->index_in(kf_id) < 0) {
      add_observation(kf, idx, by);
    } else if (kf->map_point_id(idx) == old_mp->id()) {
      kf->erase_map_point_id(idx);
    }
  }
  by->increase_found(old_mp->found());
  by->increase_visible(old_mp->visible());
  old_mp->clear_observations();
  old_mp->set_replaced_by(by->id());
  old_mp->set_bad();
  map.erase_map_point(old_mp->id());
  by->update_descriptor(map);
}

bool cull_keyframe(Map& map, KeyFrameDatabase* database, const std::shared_ptr<KeyFrame>& kf) {
  if (kf->is_bad()) return false;
  const uint32_t parent_id = kf->parent_id();
  const auto parent = map.keyframe(parent_id);
  if (parent_id == kNoId || !parent) return false;

  for (const auto& [nb_id, w] : kf->connection_weights())
    if (auto nb = map.keyframe(nb_id)) nb->erase_connection(kf->id());
  const auto ids = kf->map_point_ids();
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] == kNoId) continue;
    if (auto mp = map.map_point(ids[i])) {
      if (mp->index_in(kf->id()) == static_cast<int>(i)) {
        mp->erase_observation(kf->id());
        if (mp->num_observations() == 0) erase_map_point(map, mp);
      }
    }
    kf->erase_map_point_id(i);
  }

  // Re-attach the children: repeatedly pick the (child, candidate parent) pair with the
  // strongest covisibility, so the tree stays made of strong edges.
  std::set<uint32_t> children = kf->children();
  std::set<uint32_t> candidates{parent_id};
  while (!children.empty()) {
    uint32_t best_child = kNoId, best_parent = kNoId;
    int best_w = -1;
    for (uint32_t c : children) {
      const auto child = map.keyframe(c);
      if (!child || child->is_bad()) continue;
      for (uint32_t cand : candidates) {
        const int w = child->weight(cand);
        if (w > best_w) {
          best_w = w;
          best_child = c;
          best_parent = cand;
        }
      }
    }
    if (best_child == kNoId || best_w <= 0) break;
    const auto child = map.keyframe(best_child);
    child->set_parent(best_parent);
    if (auto p = map.keyframe(best_parent)) p->add_child(best_child);
    candidates.insert(best_child);
    children.erase(best_child);
  }
  for (uint32_t c : children) {  // no shared points with any candidate: hang on the parent
    if (auto child = map.keyframe(c)) {
      child->set_parent(parent_id);
      parent->add_child(c);
    }
  }
  parent->erase_child(kf->id());
  kf->clear_children();
  kf->clear_connections();
  kf->set_bad_relative_to_parent(kf->T_cw() * parent->T_wc());
  map.erase_keyframe(kf->id());
  if (database) database->erase(kf);
  return true;
}

}  // namespace edge_slam
