// Map object ids: KeyFrames and MapPoints are referenced by 32-bit id everywhere (maps,
// observations, wire records); kNoId marks "none".
#pragma once
#include <cstdint>

namespace edge_slam {

inline constexpr uint32_t kNoId = 0xffffffffu;

// Both sides create map points (the mobile from depth at new KeyFrames, the edge by
// triangulation and fusion), so each allocates from its own half of the id space and a map
// holding the other side's points never hands out an id the other side may also use.
inline constexpr uint32_t kMobilePointIdFirst = 0u;
inline constexpr uint32_t kEdgePointIdFirst = 0x80000000u;

}  // namespace edge_slam
