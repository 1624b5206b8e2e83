// A keyframe: the shared feature data of the frame it was made from, its pose, BoW, the
// map point id seen at each keypoint, covisibility (weights = number of shared map
// points), spanning tree parent/children and loop edges. Everything that other modules
// may change concurrently (pose, map point ids, connections) is behind a mutex.
// Related objects are referenced by id and resolved through the Map, so there are no
// ownership cycles and a map can be rebuilt from plain lists in linear time.
#pragma once
#include <Eigen/Geometry>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "edge_slam/data/bow_types.h"
#include "edge_slam/data/frame.h"
#include "edge_slam/data/frame_features.h"
#include "edge_slam/data/map_point.h"
#include "edge_slam/util/instance_count.h"

namespace edge_slam {

class BowVocabulary;
class Map;

class KeyFrame {
 public:
  // Covisibility edge threshold: keyframes sharing at least this many points are linked.
  static constexpr int kCovisibilityThreshold = 15;

  // Takes the frame's features (shared), pose, stamp and BoW (if computed).
  KeyFrame(uint32_t id, const Frame& frame);
  // Direct construction (deserialisation, tests).
  KeyFrame(uint32_t id, uint64_t frame_id, double stamp,
           std::shared_ptr<const FrameFeatures> features, const Eigen::Isometry3d& T_cw);

  uint32_t id() const { return id_; }
  uint64_t frame_id() const { return frame_id_; }
  double stamp() const { return stamp_; }
  const FrameFeatures& features() const { return *features_; }
  const std::shared_ptr<const FrameFeatures>& features_ptr() const { return features_; }

  // --- pose ---
  Eigen::Isometry3d T_cw() const;
  Eigen::Isometry3d T_wc() const;
  Eigen::Vector3d camera_center() const;
  void set_pose(const Eigen::Isometry3d& T_cw);

  // --- bag of words (set once, before the keyframe is shared) ---
  void compute_bow(const BowVocabulary& vocabulary);
  // Sets an already computed BoW (deserialisation, tests); before the keyframe is shared.
  void set_bow(BowVector bow, FeatureVector fv) {
    bow_ = std::move(bow);
    feature_vector_ = std::move(fv);
    has_bow_ = true;
  }
  bool has_bow() const { return has_bow_; }
  const BowVector& bow() const { return bow_; }
  const FeatureVector& feature_vector() const { return feature_vector_; }

  // --- map point associations (kNoId = none) ---
  uint32_t map_point_id(size_t i) const;
  std::vector<uint32_t> map_point_ids() const;
  void set_map_point_id(size_t i, uint32_t mp_id);
  void erase_map_point_id(size_t i);
  // Resolved through the map: null where there is no (good) point.
  std::vector<std::shared_ptr<MapPoint>> map_points(const Map& map) const;
  // Number of good points with at least `min_obs` observations; with depth_counts_twice a
  // keypoint with depth counts twice, as in ORB-SLAM2's RGB-D keyframe decision.
  int tracked_map_points(const Map& map, int min_obs, bool depth_counts_twice = true) const;

  // --- covisibility graph ---
  // Recounts shared observations with every other keyframe (through the map points),
  // keeps edges with weight >= kCovisibilityThreshold (or the single best one if none
  // reaches it), mirrors them into the other keyframes, and attaches this keyframe to
  // the spanning tree (parent = strongest neighbour) if it has no parent yet.
  void update_connections(const Map& map);
  void add_connection(uint32_t kf_id, int weight);
  void erase_connection(uint32_t kf_id);
  void clear_connections();
  std::map<uint32_t, int> connection_weights() const;
  int weight(uint32_t kf_id) const;
  std::vector<uint32_t> ordered_neighbours() const;  // by decreasing weight
  std::vector<uint32_t> best_covisibles(size_t n) const;
  std::vector<uint32_t> covisibles_with_weight(int min_weight) const;

  // --- spanning tree and loop edges ---
  uint32_t parent_id() const;
  void set_parent(uint32_t parent_id);  // does not touch the parent's children
  std::set<uint32_t> children() const;
  void add_child(uint32_t kf_id);
  void erase_child(uint32_t kf_id);
  void clear_children();
  std::set<uint32_t> loop_edges() const;
  void add_loop_edge(uint32_t kf_id);

  bool is_bad() const { return bad_; }
  void set_bad() { bad_ = true; }
  // Culling: marks the keyframe bad and keeps its pose relative to its (new) spanning-tree
  // parent, T_cp = T_cw * T_pw^-1, so frames that referred to it can still be placed later.
  void set_bad_relative_to_parent(const Eigen::Isometry3d& T_cp);
  Eigen::Isometry3d T_cp() const;

  std::vector<size_t> features_in_area(float x, float y, float r, int min_level = -1,
                                       int max_level = -1) const {
    std::vector<size_t> out;
    features_->grid.in_area(x, y, r, min_level, max_level, out);
    return out;
  }
  // The same into a buffer the caller reuses across queries (no allocation per query).
  void features_in_area(float x, float y, float r, int min_level, int max_level, std::vector<size_t>& out) const {
    features_->grid.in_area(x, y, r, min_level, max_level, out);
  }
  Eigen::Vector3d unproject_world(size_t i) const { return T_wc() * features_->unproject_camera(i); }

 private:
  void sort_neighbours_locked();

  const uint32_t id_;
  const uint64_t frame_id_;
  const double stamp_;
  const std::shared_ptr<const FrameFeatures> features_;

  mutable std::mutex pose_mutex_;
  Eigen::Isometry3d T_cw_;
  Eigen::Isometry3d T_cp_ = Eigen::Isometry3d::Identity();

  BowVector bow_;
  FeatureVector feature_vector_;
  bool has_bow_ = false;

  mutable std::mutex features_mutex_;
  std::vector<uint32_t> map_point_ids_;

  mutable std::mutex connections_mutex_;
  std::map<uint32_t, int> weights_;
  std::vector<uint32_t> ordered_neighbours_;
  std::vector<int> ordered_weights_;
  uint32_t parent_id_ = kNoId;
  std::set<uint32_t> children_;
  std::set<uint32_t> loop_edges_;

  std::atomic<bool> bad_{false};
  InstanceCount<KeyFrame> instance_count_;  // util/instance_count.h: both nodes' memory rows report it
};

}  // namespace edge_slam
