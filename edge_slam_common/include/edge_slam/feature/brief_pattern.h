// The 256 intensity comparisons of the ORB (rotated BRIEF) descriptor.
#pragma once
#include <array>
#include <cstdint>

namespace edge_slam {

constexpr int kBriefTests = 256;  // = 8 * kDescriptorBytes

// Bit i of the descriptor is 1 when the smoothed intensity at (x1, y1) is below the one at
// (x2, y2), offsets in pixels from the keypoint in its own (unrotated) frame. Every point
// lies within kOrbPatchRadius of the keypoint, so any rotation of it stays inside the patch.
struct BriefTest {
  int8_t x1, y1, x2, y2;
};

const std::array<BriefTest, kBriefTests>& brief_pattern();

}  // namespace edge_slam
