// Recently created map points on probation (ORB-SLAM2's MapPointCulling): a point is erased
// when tracking found it in fewer than 25% of the frames predicting it visible, or when it
// still has fewer than `min_observers` observations once two keyframes have passed since its
// creation (weighted as ORB-SLAM2 does: a keypoint with depth counts twice, so an RGB-D
// point needs two observing keyframes); after three keyframes it leaves probation.
#pragma once
#include <cstdint>
#include <list>
#include <vector>
#include <utility>

#include "edge_slam/data/map.h"

namespace edge_slam {

struct MapPointCullingParams {
  float min_found_ratio = 0.25f;
  int min_observers = 3;        // weighted; ORB-SLAM2: 2 monocular, 3 stereo / RGB-D
  uint32_t probation_keyframes = 3;
};

class RecentMapPoints {
 public:
  explicit RecentMapPoints(const MapPointCullingParams& params = {}) : params_(params) {}
  void add(uint32_t mp_id, uint32_t creation_kf_id) { points_.emplace_back(mp_id, creation_kf_id); }
  // Applies the rules against the keyframe now being processed; returns how many were erased.
  // The caller holds Map::update_mutex().
  int cull(Map& map, uint32_t current_kf_id);
  size_t size() const { return points_.size(); }

 private:
  MapPointCullingParams params_;
  std::list<std::pair<uint32_t, uint32_t>> points_;  // map point id, creating keyframe id
  // Per robot (util/robot_ids.h), the newest KeyFrame id processed: a point's age counts the
  // KeyFrames of the robot whose KeyFrame made it (ids of different robots do not compare).
  std::vector<uint32_t> newest_by_robot_;
};

}  // namespace edge_slam
