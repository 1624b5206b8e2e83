#include "edge_slam/data/keyframe.h"

#include <algorithm>
#include <unordered_map>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

KeyFrame::KeyFrame(uint32_t id, const Frame& frame)
    : KeyFrame(id, frame.id, frame.stamp, frame.features, frame.T_cw()) {
  if (frame.has_bow()) {
    bow_ = frame.bow();
    feature_vector_ = frame.feature_vector();
    has_bow_ = true;
  }
}

KeyFrame::KeyFrame(uint32_t id, uint64_t frame_id, double stamp,
                   std::shared_ptr<const FrameFeatures> features, const Eigen::Isometry3d& T_cw)
    : id_(id), frame_id_(frame_id), stamp_(stamp), features_(std::move(features)), T_cw_(T_cw) {
  map_point_ids_.assign(features_->size(), kNoId);
}

Eigen::Isometry3d KeyFrame::T_cw() const {
  std::lock_guard<std::mutex> lock(pose_mutex_);
  return T_cw_;
}
Eigen::Isometry3d KeyFrame::T_wc() const { return T_cw().inverse(); }
Eigen::Vector3d KeyFrame::camera_center() const { return T_wc().translation(); }
void KeyFrame::set_pose(const Eigen::Isometry3d& T_cw) {
  std::lock_guard<std::mutex> lock(pose_mutex_);
  T_cw_ = T_cw;
}

void KeyFrame::set_bad_relative_to_parent(const Eigen::Isometry3d& T_cp) {
  {
    std::lock_guard<std::mutex> lock(pose_mutex_);
    T_cp_ = T_cp;
  }
  bad_ = true;
}
Eigen::Isometry3d KeyFrame::T_cp() const {
  std::lock_guard<std::mutex> lock(pose_mutex_);
  return T_cp_;
}

void KeyFrame::compute_bow(const BowVocabulary& vocabulary) {
  if (has_bow_) return;
  vocabulary.transform(features_->descriptors, bow_, feature_vector_, 4);
  has_bow_ = true;
}

uint32_t KeyFrame::map_point_id(size_t i) const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  return i < map_point_ids_.size() ? map_point_ids_[i] : kNoId;
}
std::vector<uint32_t> KeyFrame::map_point_ids() const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  return map_point_ids_;
}
void KeyFrame::set_map_point_id(size_t i, uint32_t mp_id) {
  std::lock_guard<std::mutex> lock(features_mutex_);
  if (i < map_point_ids_.size()) map_point_ids_[i] = mp_id;
}
void KeyFrame::erase_map_point_id(size_t i) { set_map_point_id(i, kNoId); }

std::vector<std::shared_ptr<MapPoint>> KeyFrame::map_points(const Map& map) const {
  auto out = map.map_points(map_point_ids());
  for (auto& mp : out)
    if (mp && mp->is_bad()) mp = nullptr;
  return out;
}

int KeyFrame::tracked_map_points(const Map& map, int min_obs, bool depth_counts_twice) const {
  int n = 0;
  for (const auto& mp : map_points(map))
    if (mp && (depth_counts_twice ? mp->weighted_observations_capped(map, min_obs) : mp->num_observations()) >= min_obs) ++n;
  return n;
}

void KeyFrame::update_connections(const Map& map) {
  std::unordered_map<uint32_t, int> counts;
  for (const auto& mp : map_points(map)) {
    if (!mp) continue;
    // Visited in place: a copy of each point's observation map was most of this function's cost.
    mp->for_each_observation([&](uint32_t kf_id, int) {
      if (kf_id != id_) ++counts[kf_id];
    });
  }
  if (counts.empty()) return;

  uint32_t best_id = kNoId;
  int best_w = 0;
  std::map<uint32_t, int> strong;
  for (const auto& [kf_id, w] : counts) {
    auto other = map.keyframe(kf_id);
    if (!other || other->is_bad()) continue;
    if (w > best_w || (w == best_w && kf_id < best_id)) {
      best_w = w;
      best_id = kf_id;
    }
    if (w >= kCovisibilityThreshold) strong[kf_id] = w;
  }
  if (best_id == kNoId) return;
  if (strong.empty()) strong[best_id] = best_w;

  for (const auto& [kf_id, w] : strong)
    if (auto other = map.keyframe(kf_id)) other->add_connection(id_, w);

  std::lock_guard<std::mutex> lock(connections_mutex_);
  // Edges that other keyframes created towards us stay (with refreshed weights), so the
  // graph is the symmetric closure regardless of the order keyframes were updated in.
  std::map<uint32_t, int> merged = strong;
  for (const auto& [kf_id, w] : weights_) {
    if (merged.count(kf_id)) continue;
    const auto it = counts.find(kf_id);
    if (it != counts.end() && it->second > 0) merged[kf_id] = it->second;
  }
  weights_ = std::move(merged);
  sort_neighbours_locked();
  if (parent_id_ == kNoId) {
    // Spanning tree: attach to the strongest neighbour that existed before us.
    uint32_t parent = kNoId;
    int parent_w = 0;
    for (const auto& [kf_id, w] : weights_)
      if (kf_id < id_ && w > parent_w) {
        parent_w = w;
        parent = kf_id;
      }
    if (parent != kNoId) {
      parent_id_ = parent;
      if (auto p = map.keyframe(parent)) p->add_child(id_);
    }
  }
}

void KeyFrame::add_connection(uint32_t kf_id, int weight) {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  weights_[kf_id] = weight;
  sort_neighbours_locked();
}
void KeyFrame::erase_connection(uint32_t kf_id) {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  if (weights_.erase(kf_id)) sort_neighbours_locked();
}
void KeyFrame::clear_connections() {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  weights_.clear();
  ordered_neighbours_.clear();
  ordered_weights_.clear();
}

void KeyFrame::sort_neighbours_locked() {
  std::vector<std::pair<int, uint32_t>> v;
  v.reserve(weights_.size());
  for (const auto& [kf_id, w] : weights_) v.emplace_back(w, kf_id);
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  ordered_neighbours_.resize(v.size());
  ordered_weights_.resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    ordered_weights_[i] = v[i].first;
    ordered_neighbours_[i] = v[i].second;
  }
}

std::map<uint32_t, int> KeyFrame::connection_weights() const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  return weights_;
}
int KeyFrame::weight(uint32_t kf_id) const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  const auto it = weights_.find(kf_id);
  return it == weights_.end() ? 0 : it->second;
}
std::vector<uint32_t> KeyFrame::ordered_neighbours() const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  return ordered_neighbours_;
}
std::vector<uint32_t> KeyFrame::best_covisibles(size_t n) const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  const size_t k = std::min(n, ordered_neighbours_.size());
  return std::vector<uint32_t>(ordered_neighbours_.begin(), ordered_neighbours_.begin() + k);
}
std::vector<uint32_t> KeyFrame::covisibles_with_weight(int min_weight) const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  std::vector<uint32_t> out;
  for (size_t i = 0; i < ordered_neighbours_.size() && ordered_weights_[i] >= min_weight; ++i)
    out.push_back(ordered_neighbours_[i]);
  return out;
}

uint32_t KeyFrame::parent_id() const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  return parent_id_;
}
void KeyFrame::set_parent(uint32_t parent_id) {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  parent_id_ = parent_id;
}
std::set<uint32_t> KeyFrame::children() const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  return children_;
}
void KeyFrame::add_child(uint32_t kf_id) {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  children_.insert(kf_id);
}
void KeyFrame::erase_child(uint32_t kf_id) {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  children_.erase(kf_id);
}
void KeyFrame::clear_children() {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  children_.clear();
}
std::set<uint32_t> KeyFrame::loop_edges() const {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  return loop_edges_;
}
void KeyFrame::add_loop_edge(uint32_t kf_id) {
  std::lock_guard<std::mutex> lock(connections_mutex_);
  loop_edges_.insert(kf_id);
}

}  // namespace edge_slam
