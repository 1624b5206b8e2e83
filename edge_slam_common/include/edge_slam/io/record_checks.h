// Structural checks of wire records (io/wire_records.h) before they become map objects.
// Records arrive from the other side of the split (or from a map file), so nothing in them is
// trusted: ids, array sizes, finiteness and ranges of every field are checked here, and
// whole-update properties (unique ids, an acyclic spanning tree) in map_update_record_problem.
// Each function returns an empty string when the record is fine, otherwise what is wrong.
#pragma once
#include <string>

#include "edge_slam/io/wire_records.h"

namespace edge_slam {

// Coordinates (metres, pixels) beyond this are treated as corrupt: real maps are far
// smaller, and bounding them keeps later float -> int conversions (projection, grids) defined.
inline constexpr double kMaxRecordCoordinate = 1e5;

std::string feature_record_problem(const FeatureRecord& features);
std::string pose_problem(const Eigen::Isometry3d& T);
// The KeyFrame alone: id, stamp, pose, features, observations, new points, links.
std::string keyframe_record_problem(const KeyFrameRecord& record);
std::string map_point_record_problem(const MapPointRecord& record);
// Every KeyFrame and point, plus unique KeyFrame and point ids and no spanning-tree cycle.
std::string map_update_record_problem(const MapUpdateRecord& update);

}  // namespace edge_slam
