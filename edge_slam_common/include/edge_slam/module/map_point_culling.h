// Recently created map points on probation (ORB-SLAM2's MapPointCulling): a point is erased
// when tracking found it in fewer than 25% of the frames predicting it visible, or when it
// still has fewer than `min_observers` observations once two keyframes have passed since its
// creation (weighted as ORB-SLAM2 does: a keypoint with depth counts twice, so an RGB-D
// point needs two observing keyframes); after three keyframes it leaves probation.
//
// The found ratio needs tracking's counts (MapPoint::visible / found). In the split system
// tracking runs on the mobile, so the edge's points keep their initial 1/1 and the test never
// fired there: the mobile applies it to its recent points (refute_unfound_points) and names the
// failures in its next KeyFrame record; the edge culls the named points still on probation.
#pragma once
#include <cstdint>
#include <list>
#include <unordered_set>
#include <vector>
#include <utility>

#include "edge_slam/data/map.h"

namespace edge_slam {

struct MapPointCullingParams {
  float min_found_ratio = 0.25f;
  int min_observers = 3;        // weighted; ORB-SLAM2: 2 monocular, 3 stereo / RGB-D
  uint32_t probation_keyframes = 3;
};

// ORB-SLAM2's found-ratio test: tracking predicted the point in view in `visible` frames and
// matched it in `found` of them; too rarely found means a spurious point.
inline bool found_too_rarely(const MapPoint& mp, const MapPointCullingParams& params) {
  return mp.found_ratio() < params.min_found_ratio;
}

// Whether a point made by KeyFrame `made_by` is still on probation when KeyFrame `current` is
// processed: both of one robot (ids of different robots do not compare) and `current` 1 to
// probation_keyframes KeyFrames later.
bool on_probation(uint32_t made_by, uint32_t current, const MapPointCullingParams& params);

// The mobile's half of the found-ratio test: the points of `map` on probation for the KeyFrame
// `new_kf_id` that tracking found too rarely, erased from `map` (as the test would erase them
// in a monolithic run); returns their ids for the KeyFrame record.
std::vector<uint32_t> refute_unfound_points(Map& map, uint32_t new_kf_id, const MapPointCullingParams& params);

class RecentMapPoints {
 public:
  explicit RecentMapPoints(const MapPointCullingParams& params = {}) : params_(params) {}
  void add(uint32_t mp_id, uint32_t creation_kf_id) { points_.emplace_back(mp_id, creation_kf_id); }
  // Applies the rules against the keyframe now being processed; returns how many were erased.
  // `refuted`: points the mobile's tracking found too rarely (refute_unfound_points), erased
  // when on probation here, counted in *num_refuted. The caller holds Map::update_mutex().
  int cull(Map& map, uint32_t current_kf_id, const std::unordered_set<uint32_t>* refuted = nullptr,
           int* num_refuted = nullptr);
  size_t size() const { return points_.size(); }

 private:
  MapPointCullingParams params_;
  std::list<std::pair<uint32_t, uint32_t>> points_;  // map point id, creating keyframe id
  // Per robot (util/robot_ids.h), the newest KeyFrame id processed: a point's age counts the
  // KeyFrames of the robot whose KeyFrame made it (ids of different robots do not compare).
  std::vector<uint32_t> newest_by_robot_;
};

}  // namespace edge_slam
