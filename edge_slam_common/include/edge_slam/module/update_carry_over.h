// Local-Map update installation, the mobile's KeyFrames the update could not contain: an update
// is built from what the edge had received when it started building, so the KeyFrames the
// mobile made since (typically the last 0-2) are not in it. The paper's full replacement drops
// them, and with them the points tracking is following right now. carry_over_keyframes puts
// them back into the freshly installed Local-Map: their points that the update holds are linked
// to the edge's version, the others come along, and everything is moved by the correction the
// update applied around them (the same rigid change as at their spanning-tree parent, or at the
// KeyFrame they share most points with), so the carried KeyFrames sit where the edge put their
// neighbours.
#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

struct CarryOverResult {
  size_t keyframes = 0;       // KeyFrames carried into the new map
  size_t points_carried = 0;  // their points the update did not hold
  size_t points_linked = 0;   // their points the update did hold (observation added to the edge's version)
};

// `ids`: the KeyFrames to carry, oldest first, taken from `old_map` (the Local-Map before the
// swap). The caller holds new_map's update mutex (tracking is paused). A KeyFrame the old map
// does not hold, or one the new map already has, is skipped. One linked to no KeyFrame of the
// update (nor to a carried one) follows the correction at `fallback_anchor` (kNoId: none).
CarryOverResult carry_over_keyframes(Map& new_map, const Map& old_map, const std::vector<uint32_t>& ids,
                                     KeyFrameDatabase* database, uint32_t fallback_anchor = kNoId);

// The rigid change x_new = C * x_old of the map around a KeyFrame, from a KeyFrame present in both
// maps: C = T_wc(new) * T_cw(old). Identity when the anchor is in only one of them.
Eigen::Isometry3d map_correction_at(const Map& new_map, const Map& old_map, uint32_t anchor_id);

}  // namespace edge_slam
