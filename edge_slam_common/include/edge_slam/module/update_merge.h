// Installing a Local-Map update by merging it into the live Local-Map (edge_slam/update_install:
// merge), in time proportional to the update, not to the Local-Map, because tracking is paused
// meanwhile. An update holds update_size KeyFrames around the camera; the Local-Map also holds
// the places tracking may turn back to. The update's KeyFrames and points replace their live
// copies (the edge's optimised versions win), the other live KeyFrames stay, and they and their
// own points follow the correction the update applied around them: the rigid change at their
// spanning-tree parent or strongest covisible KeyFrame in the update (else at a carried ancestor,
// else at `fallback_anchor`), so the whole Local-Map sits where the edge put its neighbours.
#pragma once
#include <cstdint>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

struct MergeResult {
  size_t keyframes_replaced = 0;  // live KeyFrames the update held a newer version of
  size_t keyframes_added = 0;     // update KeyFrames the Local-Map did not have
  size_t keyframes_kept = 0;      // live KeyFrames the update did not hold, corrected and kept
  size_t points_replaced = 0, points_added = 0, points_moved = 0;
  size_t points_dropped = 0;  // live points only the replaced KeyFrames observed and the update does not hold
};

// `staged`: the update's KeyFrames and points, built and linked off-line (stage_update); its
// objects move into `live` (staged is left empty). The caller holds live's update mutex.
// `database` (may be null) is updated incrementally: replaced KeyFrames out, update KeyFrames in.
MergeResult merge_update(Map& live, Map& staged, KeyFrameDatabase* database);

}  // namespace edge_slam
