// Map objects <-> wire records (io/wire_records.h): what the mobile sends for a new KeyFrame,
// what the edge packs into a Local-Map update, and the receiving side's linear-time rebuild.
// The receiver trusts only its own camera configuration: a record whose intrinsics differ
// from it is rejected, so keypoints are never interpreted in the wrong camera.
#pragma once
#include <memory>
#include <string>
#include <unordered_set>

#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/map_point.h"
#include "edge_slam/io/wire_records.h"

namespace edge_slam {

class BowVocabulary;

CameraRecord to_camera_record(const PinholeCamera& camera);
FeatureRecord to_feature_record(const FrameFeatures& features);

// A KeyFrame with its observations; points whose ids are in `created_point_ids` travel in full
// as new points instead (the mobile -> edge message). Links (parent, covisibility) included.
KeyFrameRecord to_record(const KeyFrame& kf, const Map& map,
                         const std::unordered_set<uint32_t>& created_point_ids = {});
MapPointRecord to_record(const MapPoint& mp);
FrameRecord to_record(const Frame& frame, uint64_t seq);

// Empty when the record's camera matches `camera`; otherwise what differs.
std::string camera_mismatch(const CameraRecord& record, const PinholeCamera& camera);

// Feature data rebuilt from a record (keypoints are already undistorted): depth, virtual
// right coordinates and the search grid are recomputed. Throws std::invalid_argument on a
// camera mismatch or inconsistent sizes.
std::shared_ptr<const FrameFeatures> features_from_record(const FeatureRecord& features,
                                                          const CameraRecord& record_camera,
                                                          const PinholeCamera& camera,
                                                          std::shared_ptr<const ScalePyramid> pyramid);

// A KeyFrame whose map point ids come from the record's observations and new points.
std::shared_ptr<KeyFrame> keyframe_from_record(const KeyFrameRecord& record, const PinholeCamera& camera,
                                               std::shared_ptr<const ScalePyramid> pyramid);
std::shared_ptr<MapPoint> map_point_from_record(const MapPointRecord& record);
// A point created by `kf` (mobile -> edge): descriptor of its source keypoint, kf as reference.
std::shared_ptr<MapPoint> map_point_from_new_point(const NewPointRecord& record, const KeyFrame& kf);

struct RebuildStats {
  size_t keyframes = 0;
  size_t map_points = 0;
  size_t dropped_observations = 0;  // observations of points the update did not carry
};

// An update's KeyFrames and MapPoints built and linked (Map::rebuild: observations,
// covisibility, spanning tree; BoW when a vocabulary is given) in a private map, ready to be
// installed. All the linear work of applying an update, done without touching the live map.
struct StagedUpdate {
  std::unique_ptr<Map> map;
  RebuildStats stats;
};
// Throws std::invalid_argument on a bad record.
StagedUpdate stage_update(const MapUpdateRecord& update, const PinholeCamera& camera,
                          std::shared_ptr<const ScalePyramid> pyramid, const BowVocabulary* vocabulary);
// Swaps the staged content into `map` (O(1), under its update_mutex). `staged` then holds the
// old content: drop it outside any lock the caller wants short.
void install_update(Map& map, StagedUpdate& staged);

// stage_update + install_update. Throws std::invalid_argument (map untouched) on a bad record.
RebuildStats rebuild_from_update(Map& map, const MapUpdateRecord& update, const PinholeCamera& camera,
                                 std::shared_ptr<const ScalePyramid> pyramid, const BowVocabulary* vocabulary);

}  // namespace edge_slam
