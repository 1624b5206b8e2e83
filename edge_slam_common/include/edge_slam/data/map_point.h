// A 3-D landmark: position, representative ORB descriptor, mean viewing direction,
// scale-invariance distance range and the keyframes observing it (keyframe id ->
// keypoint index). Thread-safe: position and observation data have their own mutexes.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>

#include "edge_slam/data/scale_pyramid.h"
#include "edge_slam/feature/descriptor_distance.h"
#include "edge_slam/util/ids.h"
#include "edge_slam/util/instance_count.h"

namespace edge_slam {

class Map;
class KeyFrame;
using Descriptor = std::array<uint8_t, kDescriptorBytes>;


class MapPoint {
 public:
  MapPoint(uint32_t id, const Eigen::Vector3d& position, uint32_t reference_kf_id);

  uint32_t id() const { return id_; }

  // Position, normal and distance range read under one lock (for projection tests).
  struct Geometry {
    Eigen::Vector3d position, normal;
    float min_distance, max_distance;  // with the 0.8 / 1.2 margins, as min/max_distance()
    float max_level0_distance;         // raw, for scale prediction
  };
  Geometry geometry() const;

  Eigen::Vector3d position() const;
  void set_position(const Eigen::Vector3d& p);
  Eigen::Vector3d normal() const;
  float min_distance() const;  // scale-invariance range (0.8 / 1.2 margins applied)
  float max_distance() const;
  void set_normal_and_distances(const Eigen::Vector3d& normal, float min_d, float max_d);
  // Moves the point rigidly (position and viewing normal) under one lock, once per `pass`: a
  // second call with the same pass does nothing and returns false (a Local-Map update moves each
  // point once, whichever of its KeyFrames reaches it first). Passes are > 0.
  bool transform_once(const Eigen::Isometry3d& C, uint64_t pass);
  // Pyramid level at which the point should appear when seen from distance `dist`.
  int predict_level(double dist, const ScalePyramid& pyramid) const;

  Descriptor descriptor() const;
  void set_descriptor(const uint8_t* d);

  void add_observation(uint32_t kf_id, int keypoint_index);
  void erase_observation(uint32_t kf_id);
  void clear_observations();
  std::map<uint32_t, int> observations() const;
  // Calls f(kf_id, keypoint_index) for each observation in id order, under the point's lock
  // and without copying the map (observations() allocates a copy). f must not call back into
  // this point's observation or descriptor accessors (the lock is not recursive).
  template <typename F>
  void for_each_observation(F&& f) const {
    std::lock_guard<std::mutex> lock(features_mutex_);
    for (const auto& [kf_id, idx] : observations_) f(kf_id, idx);
  }
  int num_observations() const;
  // Observations counted as ORB-SLAM2 does for RGB-D: 2 for a keypoint with depth (a
  // virtual stereo measurement), 1 otherwise; observing keyframes missing from `map` count 1.
  int weighted_observations(const Map& map) const;
  // min(weighted_observations(map), cap) without visiting more observations than needed: each
  // weighs at least 1, so the first `cap` decide it. Tracking asks this of every reference
  // KeyFrame point on every frame (KeyFrame condition 4), where the full count copied the
  // observation map and looked up every observer: ~1 ms per frame on fr1_rpy.
  int weighted_observations_capped(const Map& map, int cap) const;
  int index_in(uint32_t kf_id) const;  // -1 when not observed by that keyframe

  uint32_t reference_kf_id() const;
  void set_reference_kf_id(uint32_t id);

  // Tracking statistics: how often the point was predicted visible, and actually matched.
  void increase_visible(int n = 1) { visible_ += n; }
  void increase_found(int n = 1) { found_ += n; }
  int visible() const { return visible_; }
  int found() const { return found_; }
  float found_ratio() const { return visible_ > 0 ? static_cast<float>(found_) / visible_ : 0.f; }

  // Hints the CPU to fetch the cache lines a projection test (id, flags, geometry) or a
  // descriptor comparison reads, ahead of use: loops over ~10^4 points per frame call it a few
  // points in advance so the memory latency overlaps the work on the current point.
  void prefetch_geometry() const {
    __builtin_prefetch(this);
    __builtin_prefetch(reinterpret_cast<const char*>(this) + 64);
    __builtin_prefetch(reinterpret_cast<const char*>(this) + 112);
  }
  void prefetch_descriptor() const {
    __builtin_prefetch(this);
    __builtin_prefetch(&descriptor_);
    __builtin_prefetch(reinterpret_cast<const char*>(&descriptor_) + 31);
  }

  bool is_bad() const { return bad_; }
  void set_bad() { bad_ = true; }
  // Id of the point that replaced this one after a fusion (kNoId if none), so holders of
  // a stale pointer can follow it.
  uint32_t replaced_by() const { return replaced_by_; }
  void set_replaced_by(uint32_t id) { replaced_by_ = id; }

  // Recompute from the observing keyframes held in `map` (missing ones are skipped):
  // the descriptor with least median distance to the others, and the mean viewing normal
  // plus distance range from the reference keyframe's observation.
  void update_descriptor(const Map& map);
  void update_normal_and_depth(const Map& map);

 private:
  // Layout: what the tracker's local-map search reads for every one of ~10^4 points per frame
  // (id, bad flag, visibility counter, then the geometry) comes first, in the cache lines the
  // shared_ptr control block is allocated next to.
  const uint32_t id_;
  std::atomic<bool> bad_{false};
  std::atomic<int> visible_{1}, found_{1};
  std::atomic<uint32_t> replaced_by_{0xffffffffu};
  mutable std::mutex pos_mutex_;
  Eigen::Vector3d position_;
  Eigen::Vector3d normal_ = Eigen::Vector3d::Zero();
  float min_distance_ = 0.f, max_distance_ = 0.f;
  uint64_t last_transform_pass_ = 0;

  mutable std::mutex features_mutex_;
  Descriptor descriptor_{};
  std::map<uint32_t, int> observations_;
  uint32_t reference_kf_id_;
  InstanceCount<MapPoint> instance_count_;  // util/instance_count.h: both nodes' memory rows report it
};

// One observation's weight in MapPoint::weighted_observations: 2 when keypoint `keypoint_index`
// of `kf` has depth, 1 otherwise or when kf is null (not in the map).
int observation_weight(const KeyFrame* kf, int keypoint_index);

}  // namespace edge_slam
