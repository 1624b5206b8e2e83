// Procedural surface textures for the synthetic room. Every surface gets its own seeded mix of
// multi-octave noise and many shapes at many scales (posters with glyph "text", tiles, book
// spines, stains...), so FAST finds plenty of corners at any distance and no two surfaces look
// alike (place recognition needs distinct places).
#pragma once
#include "edge_slam/sim/random.h"

#include <opencv2/core.hpp>

namespace edge_slam {

enum class SurfaceStyle { kWall, kFloor, kCeiling, kFurniture };

// A CV_8UC3 (BGR) texture covering width_m x height_m at texels_per_m. Rows run along the
// surface's v axis, columns along its u axis (see Scene). Deterministic in rng's state.
cv::Mat paint_surface(SurfaceStyle style, double width_m, double height_m, double texels_per_m,
                      SplitMix64& rng);

}  // namespace edge_slam
