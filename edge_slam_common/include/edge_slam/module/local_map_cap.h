// Keeps the mobile's Local-Map at a fixed size (paper 4.7: constant memory on the mobile):
// beyond `cap` KeyFrames the oldest ones are dropped from the Local-Map only. They were already
// queued for the edge when created, so nothing mapped is lost; the Global-Map keeps them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

class ConfigMap;

// The Local-Map's size, which the mobile (cap, eq. (1)'s LMU) and the edge (update size, the
// relocalization update's cap) must agree on: edge_slam/update_size and edge_slam/local_map_cap.
struct LocalMapSize {
  int update_size = 6;  // KeyFrames per periodic update (paper: 6)
  size_t cap = 50;      // KeyFrames kept in the mobile's Local-Map
};
// The one loader of both keys; the cap holds at least one update, or an accepted update would
// be cut down at once. Throws naming the key and the range.
LocalMapSize load_local_map_size(const ConfigMap& cfg);

// Drops the oldest KeyFrames (by stamp, then id) until at most `cap` remain, never one of
// `keep` (the tracker's reference and the newest KeyFrame). Each dropped KeyFrame loses its
// observations and covisibility links, points left unobserved go, its children become roots.
// Returns the ids dropped. The caller holds whatever excludes tracking (MobileSession's lock).
std::vector<uint32_t> enforce_local_map_cap(Map& map, KeyFrameDatabase* database, size_t cap,
                                            const std::vector<uint32_t>& keep);

}  // namespace edge_slam
