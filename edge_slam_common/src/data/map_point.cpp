#include "edge_slam/data/map_point.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

MapPoint::MapPoint(uint32_t id, const Eigen::Vector3d& position, uint32_t reference_kf_id)
    : id_(id), position_(position), reference_kf_id_(reference_kf_id) {}

MapPoint::Geometry MapPoint::geometry() const {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  return {position_, normal_, 0.8f * min_distance_, 1.2f * max_distance_, max_distance_};
}

Eigen::Vector3d MapPoint::position() const {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  return position_;
}
void MapPoint::set_position(const Eigen::Vector3d& p) {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  position_ = p;
}
bool MapPoint::transform_once(const Eigen::Isometry3d& C, uint64_t pass) {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  if (last_transform_pass_ == pass) return false;
  last_transform_pass_ = pass;
  position_ = C * position_;
  normal_ = C.linear() * normal_;
  return true;
}

Eigen::Vector3d MapPoint::normal() const {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  return normal_;
}
float MapPoint::min_distance() const {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  return 0.8f * min_distance_;
}
float MapPoint::max_distance() const {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  return 1.2f * max_distance_;
}
void MapPoint::set_normal_and_distances(const Eigen::Vector3d& normal, float min_d, float max_d) {
  std::lock_guard<std::mutex> lock(pos_mutex_);
  normal_ = normal;
  min_distance_ = min_d;
  max_distance_ = max_d;
}

int MapPoint::predict_level(double dist, const ScalePyramid& pyramid) const {
  float max_d;
  {
    std::lock_guard<std::mutex> lock(pos_mutex_);
    max_d = max_distance_;
  }
  return pyramid.predict_level(max_d, dist);
}

Descriptor MapPoint::descriptor() const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  return descriptor_;
}
void MapPoint::set_descriptor(const uint8_t* d) {
  std::lock_guard<std::mutex> lock(features_mutex_);
  std::memcpy(descriptor_.data(), d, kDescriptorBytes);
}

void MapPoint::add_observation(uint32_t kf_id, int keypoint_index) {
  std::lock_guard<std::mutex> lock(features_mutex_);
  observations_[kf_id] = keypoint_index;
}
void MapPoint::erase_observation(uint32_t kf_id) {
  std::lock_guard<std::mutex> lock(features_mutex_);
  observations_.erase(kf_id);
  if (reference_kf_id_ == kf_id && !observations_.empty())
    reference_kf_id_ = observations_.begin()->first;
}
void MapPoint::clear_observations() {
  std::lock_guard<std::mutex> lock(features_mutex_);
  observations_.clear();
}
std::map<uint32_t, int> MapPoint::observations() const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  return observations_;
}
int MapPoint::num_observations() const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  return static_cast<int>(observations_.size());
}
int observation_weight(const KeyFrame* kf, int idx) {
  const bool stereo = kf && idx >= 0 && static_cast<size_t>(idx) < kf->features().size() &&
                      kf->features().right_x[idx] >= 0;
  return stereo ? 2 : 1;
}

int MapPoint::weighted_observations(const Map& map) const {
  int n = 0;
  for (const auto& [kf_id, idx] : observations()) n += observation_weight(map.keyframe(kf_id).get(), idx);
  return n;
}

int MapPoint::weighted_observations_capped(const Map& map, int cap) const {
  constexpr int kMaxCap = 16;  // the first observations are copied to the stack, not the heap
  if (cap <= 0) return 0;
  if (cap > kMaxCap) return std::min(weighted_observations(map), cap);
  std::pair<uint32_t, int> first[kMaxCap];
  int n = 0;
  {
    std::lock_guard<std::mutex> lock(features_mutex_);
    for (const auto& obs : observations_) {
      if (n == cap) break;
      first[n++] = obs;
    }
  }
  // The keyframes are looked up outside the point's lock (the map has its own).
  int w = 0;
  for (int i = 0; i < n && w < cap; ++i) w += observation_weight(map.keyframe(first[i].first).get(), first[i].second);
  return std::min(w, cap);
}

int MapPoint::index_in(uint32_t kf_id) const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  const auto it = observations_.find(kf_id);
  return it == observations_.end() ? -1 : it->second;
}
uint32_t MapPoint::reference_kf_id() const {
  std::lock_guard<std::mutex> lock(features_mutex_);
  return reference_kf_id_;
}
void MapPoint::set_reference_kf_id(uint32_t id) {
  std::lock_guard<std::mutex> lock(features_mutex_);
  reference_kf_id_ = id;
}

void MapPoint::update_descriptor(const Map& map) {
  std::vector<const uint8_t*> descs;
  std::vector<std::shared_ptr<KeyFrame>> keep_alive;
  for (const auto& [kf_id, idx] : observations()) {
    auto kf = map.keyframe(kf_id);
    if (!kf || kf->is_bad() || idx < 0 || static_cast<size_t>(idx) >= kf->features().size()) continue;
    descs.push_back(kf->features().descriptor(idx));
    keep_alive.push_back(std::move(kf));
  }
  if (descs.empty()) return;
  const size_t n = descs.size();
  std::vector<int> dist(n * n, 0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      dist[i * n + j] = dist[j * n + i] = descriptor_distance(descs[i], descs[j]);
  size_t best = 0;
  int best_median = INT32_MAX;
  std::vector<int> row(n);
  for (size_t i = 0; i < n; ++i) {
    std::copy(dist.begin() + i * n, dist.begin() + (i + 1) * n, row.begin());
    std::nth_element(row.begin(), row.begin() + (n - 1) / 2, row.end());
    const int median = row[(n - 1) / 2];
    if (median < best_median) {
      best_median = median;
      best = i;
    }
  }
  set_descriptor(descs[best]);
}

void MapPoint::update_normal_and_depth(const Map& map) {
  const auto obs = observations();
  if (obs.empty()) return;
  const Eigen::Vector3d p = position();
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (const auto& [kf_id, idx] : obs) {
    const auto kf = map.keyframe(kf_id);
    if (!kf) continue;
    const Eigen::Vector3d v = p - kf->camera_center();
    if (v.norm() > 0) {
      normal_sum += v.normalized();
      ++n;
    }
  }
  auto ref = map.keyframe(reference_kf_id());
  int ref_idx = ref ? ref->features().size() > 0 ? index_in(ref->id()) : -1 : -1;
  if (!ref || ref_idx < 0) {  // fall back to any observing keyframe
    for (const auto& [kf_id, idx] : obs) {
      ref = map.keyframe(kf_id);
      if (ref) {
        ref_idx = idx;
        break;
      }
    }
  }
  if (!ref || n == 0 || ref_idx < 0) return;
  const ScalePyramid& pyr = *ref->features().pyramid;
  const double dist = (p - ref->camera_center()).norm();
  const int level = ref->features().keys_un[ref_idx].octave;
  const float max_d = static_cast<float>(dist * pyr.scale_factors[level]);
  const float min_d = max_d / pyr.scale_factors[pyr.num_levels - 1];
  set_normal_and_distances(normal_sum.normalized(), min_d, max_d);
}

}  // namespace edge_slam
