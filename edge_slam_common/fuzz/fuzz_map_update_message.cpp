// Fuzz target: bytes -> edge_slam_msgs::MapUpdate -> MapUpdateRecord -> the mobile's Local-Map
// rebuilt from it (rebuild_from_update), then the graph queries tracking makes on it.
#include <edge_slam/data/map.h>
#include <edge_slam/io/map_records.h>
#include <edge_slam_bridge/checked_deserialization.h>

#include "fuzz_support.h"

using namespace edge_slam;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  edge_slam_msgs::MapUpdate msg;
  if (!deserialize_checked(data, size, msg, fuzz::limits()).ok) return 0;
  MapUpdateRecord record;
  if (!from_message(msg, record, fuzz::limits()).ok) return 0;
  Map map;
  try {
    rebuild_from_update(map, record, fuzz::camera(), fuzz::pyramid(), fuzz::vocabulary().get());
  } catch (const std::invalid_argument&) {
    return 0;
  }
  for (const auto& kf : map.keyframes()) {
    kf->map_points(map);
    kf->best_covisibles(10);
    kf->tracked_map_points(map, 1);
    for (uint32_t child : kf->children()) map.keyframe(child);
  }
  for (const auto& mp : map.map_points()) {
    mp->update_normal_and_depth(map);
    mp->predict_level(1.0, *fuzz::pyramid());
  }
  return 0;
}
