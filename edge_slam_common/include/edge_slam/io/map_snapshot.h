// A live Global-Map <-> MapSnapshot (io/map_file.h). Taking a snapshot only copies records, so
// it can run under the map lock while the file I/O happens outside it; restoring builds every
// object first (a bad snapshot throws before anything is touched) and then installs them.
#pragma once
#include <memory>
#include <vector>

#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/io/map_file.h"

namespace edge_slam {

class BowVocabulary;

// Good KeyFrames and map points with their links and the id counters. The caller holds
// map.update_mutex() so that no module changes the map half-way through.
MapSnapshot snapshot_map(const Map& map);

struct MapObjects {
  std::vector<std::shared_ptr<KeyFrame>> keyframes;  // BoW computed when a vocabulary was given
  std::vector<std::shared_ptr<MapPoint>> points;
};
// Throws std::invalid_argument on a record that fails its checks or a camera mismatch.
MapObjects map_objects_from_snapshot(const MapSnapshot& snapshot, const PinholeCamera& camera,
                                     std::shared_ptr<const ScalePyramid> pyramid, const BowVocabulary* vocabulary);

// Replaces the map's content with the objects (observations and children re-linked), then
// restores the saved covisibility weights, loop edges and id counters, and indexes every
// KeyFrame with a BoW in `database` (cleared first). Links to KeyFrames the snapshot does not
// hold are dropped. The caller holds map.update_mutex().
void install_snapshot(const MapSnapshot& snapshot, const MapObjects& objects, Map& map, KeyFrameDatabase& database);

}  // namespace edge_slam
