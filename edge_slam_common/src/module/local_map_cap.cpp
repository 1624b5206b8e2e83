#include "edge_slam/module/local_map_cap.h"

#include <algorithm>

#include "edge_slam/data/map_edit.h"
#include "edge_slam/io/config_file.h"

namespace edge_slam {

LocalMapSize load_local_map_size(const ConfigMap& cfg) {
  LocalMapSize s;
  s.update_size = cfg.get_int_or("edge_slam/update_size", 6, 1, 1000);
  s.cap = static_cast<size_t>(cfg.get_int_or("edge_slam/local_map_cap", 50, s.update_size, 100000));
  return s;
}
namespace {

void drop_keyframe(Map& map, KeyFrameDatabase* database, const std::shared_ptr<KeyFrame>& kf) {
  for (const auto& [nb_id, w] : kf->connection_weights())
    if (auto nb = map.keyframe(nb_id)) nb->erase_connection(kf->id());
  const auto ids = kf->map_point_ids();
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] == kNoId) continue;
    if (auto mp = map.map_point(ids[i])) erase_observation(map, kf, mp);
  }
  for (uint32_t c : kf->children())
    if (auto child = map.keyframe(c)) child->set_parent(kNoId);
  if (auto parent = map.keyframe(kf->parent_id())) parent->erase_child(kf->id());
  kf->clear_children();
  kf->clear_connections();
  kf->set_bad();
  map.erase_keyframe(kf->id());
  if (database) database->erase(kf);
}

}  // namespace

std::vector<uint32_t> enforce_local_map_cap(Map& map, KeyFrameDatabase* database, size_t cap,
                                            const std::vector<uint32_t>& keep) {
  std::vector<uint32_t> dropped;
  if (map.num_keyframes() <= cap) return dropped;
  std::vector<std::shared_ptr<KeyFrame>> kfs = map.keyframes();
  std::sort(kfs.begin(), kfs.end(), [](const auto& a, const auto& b) {
    return a->stamp() != b->stamp() ? a->stamp() < b->stamp() : a->id() < b->id();
  });
  for (const auto& kf : kfs) {
    if (map.num_keyframes() <= cap) break;
    if (std::find(keep.begin(), keep.end(), kf->id()) != keep.end()) continue;
    drop_keyframe(map, database, kf);
    dropped.push_back(kf->id());
  }
  return dropped;
}

}  // namespace edge_slam
