// Patch geometry shared by detection, orientation and the descriptor.
#pragma once

namespace edge_slam {

constexpr int kOrbPatchSize = 31;                   // side of the square descriptor patch
constexpr int kOrbPatchRadius = kOrbPatchSize / 2;  // 15: orientation disc and test-point radius
// Keypoints stay this far from every level border: the patch radius, plus margin for
// rounding rotated test points and the 7x7 blur, so no lookup ever leaves the image.
constexpr int kOrbEdgeBorder = 19;
constexpr int kOrbFastCellSize = 30;  // side of the FAST detection grid cells, level pixels

}  // namespace edge_slam
