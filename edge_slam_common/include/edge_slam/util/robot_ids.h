// Ids when one edge serves several mobiles (issue #16): every KeyFrame and map point id names
// the robot that made it, so records from all robots share one Global-Map without collisions
// and a record carrying another robot's ids is recognised (and refused) on arrival.
//   KeyFrames:          robot r owns [r << 24, (r + 1) << 24)               16.7 M per robot
//   mobile-made points: robot r owns [r << 27, (r + 1) << 27)               134 M per robot
// Edge-made points keep the edge's half of the id space ([2^31, kNoId)): the edge holds one
// Global-Map for all robots (merged or not yet), so one allocator hands them out.
// Robot 0 is the single un-namespaced mobile of a one-robot deployment: its spaces start where
// the one-robot ids always started, so a one-robot run makes the same ids as before.
#pragma once
#include <cstdint>

#include "edge_slam/util/ids.h"

namespace edge_slam {

inline constexpr int kMaxRobots = 16;

struct IdSpace {
  uint32_t first = 0, end = kNoId;  // [first, end)
  bool contains(uint32_t id) const { return id >= first && id < end; }
};

inline bool valid_robot_index(int robot) { return robot >= 0 && robot < kMaxRobots; }
inline IdSpace keyframe_id_space(int robot) {
  return {static_cast<uint32_t>(robot) << 24, static_cast<uint32_t>(robot + 1) << 24};
}
inline IdSpace mobile_point_id_space(int robot) {
  return {static_cast<uint32_t>(robot) << 27, static_cast<uint32_t>(robot + 1) << 27};
}
// The robot whose mobile made this KeyFrame (kNoId: -1).
inline int robot_of_keyframe(uint32_t kf_id) { return kf_id == kNoId ? -1 : static_cast<int>(kf_id >> 24); }

}  // namespace edge_slam
