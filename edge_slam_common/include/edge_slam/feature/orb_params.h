// Tunables of the ORB extractor, with the ORB-SLAM2 defaults.
#pragma once

namespace edge_slam {

struct OrbParams {
  int num_features = 1000;      // total keypoints wanted over all pyramid levels
  float scale_factor = 1.2f;    // scale ratio between consecutive pyramid levels
  int num_levels = 8;           // pyramid levels (level 0 = full resolution)
  int ini_fast_threshold = 20;  // FAST threshold tried first in every grid cell
  int min_fast_threshold = 7;   // retry threshold for cells where the first try found nothing
};

// Throws std::invalid_argument if the parameters cannot describe a working extractor.
void validate_orb_params(const OrbParams& params);

}  // namespace edge_slam
