#include "edge_slam/split/memory_row.h"

#include "edge_slam/data/frame_features.h"
#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map_point.h"
#include "edge_slam/util/instance_count.h"

namespace edge_slam {

std::string memory_row_detail(const HeapUsage& heap, const char* map_name, size_t map_keyframes, size_t map_points) {
  const std::string map(map_name);
  return "in_use_kb=" + std::to_string(heap.in_use_bytes / 1024) +
         " kept_free_kb=" + std::to_string(heap.kept_free_bytes / 1024) +
         " arena_kb=" + std::to_string(heap.arena_bytes / 1024) +
         " mapped_kb=" + std::to_string(heap.mapped_bytes / 1024) +
         " keyframes_alive=" + std::to_string(InstanceCount<KeyFrame>::alive()) +
         " points_alive=" + std::to_string(InstanceCount<MapPoint>::alive()) +
         " features_alive=" + std::to_string(InstanceCount<FrameFeatures>::alive()) + " " + map +
         "_keyframes=" + std::to_string(map_keyframes) + " " + map + "_points=" + std::to_string(map_points);
}

}  // namespace edge_slam
