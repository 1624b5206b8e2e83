// Duplicate fusion after triangulation (ORB-SLAM2's SearchInNeighbors, RGB-D): the new
// keyframe's points are projected into its 10 best covisibles and their 5 best covisibles,
// and all those keyframes' points into the new keyframe; duplicates are merged (see fuse()).
// Then the new keyframe's points get fresh descriptors and normals and its covisibility is
// recomputed. The caller holds Map::update_mutex(); returns the number of fusions.
#pragma once
#include <memory>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

int fuse_with_neighbours(Map& map, const std::shared_ptr<KeyFrame>& kf, size_t num_neighbours = 10,
                         size_t num_second_neighbours = 5);

}  // namespace edge_slam
