// Map object ids: KeyFrames and MapPoints are referenced by 32-bit id everywhere (maps,
// observations, wire records); kNoId marks "none".
#pragma once
#include <cstdint>

namespace edge_slam {

inline constexpr uint32_t kNoId = 0xffffffffu;

}  // namespace edge_slam
