// Rotation-consistency check for a set of matches: the keypoint angle differences of
// correct matches agree (the camera rolls as a whole), so matches outside the three most
// populated 12-degree bins are rejected.
#pragma once
#include <vector>

namespace edge_slam {

class RotationHistogram {
 public:
  static constexpr int kBins = 30;

  // angle_a/angle_b are the keypoint angles in degrees; `match_index` is returned by
  // inconsistent() for matches to reject.
  void add(float angle_a, float angle_b, int match_index);
  // Indices of matches outside the kept bins (bins with fewer than 10% of the
  // largest bin's votes are not kept even if among the three largest).
  std::vector<int> inconsistent() const;

 private:
  std::vector<int> bins_[kBins];
};

}  // namespace edge_slam
