#include "edge_slam/feature/orb_params.h"

#include <stdexcept>
#include <string>

namespace edge_slam {

void validate_orb_params(const OrbParams& p) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("OrbParams: " + what); };
  if (p.num_features < 0) fail("num_features must be >= 0");
  if (!(p.scale_factor > 1.0f)) fail("scale_factor must be > 1");
  if (p.num_levels < 1 || p.num_levels > 32) fail("num_levels must be in [1, 32]");
  if (p.ini_fast_threshold < 1 || p.ini_fast_threshold > 255) fail("ini_fast_threshold must be in [1, 255]");
  if (p.min_fast_threshold < 1 || p.min_fast_threshold > 255) fail("min_fast_threshold must be in [1, 255]");
}

}  // namespace edge_slam
