#include "edge_slam/data/map.h"

#include <algorithm>

namespace edge_slam {
namespace {
template <typename T>
std::vector<std::shared_ptr<T>> sorted_values(const FlatIdMap<std::shared_ptr<T>>& m) {
  std::vector<std::shared_ptr<T>> out;
  out.reserve(m.size());
  m.for_each([&](uint32_t, const std::shared_ptr<T>& v) { out.push_back(v); });
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a->id() < b->id(); });
  return out;
}
// Past the highest id held in [first, end): where an allocator over that space goes on.
template <typename T>
uint32_t next_id_in(const FlatIdMap<std::shared_ptr<T>>& m, uint32_t first, uint32_t end) {
  uint32_t next = first;
  m.for_each([&](uint32_t id, const std::shared_ptr<T>&) {
    if (id >= first && id < end) next = std::max(next, id + 1);
  });
  return next;
}
void raise_to(std::atomic<uint32_t>& counter, uint32_t value) {
  uint32_t cur = counter.load();
  while (cur < value && !counter.compare_exchange_weak(cur, value)) {
  }
}
}  // namespace

void Map::add_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.put(kf->id(), kf);
  raise_keyframe_ids_past(kf->id());
}
void Map::add_map_point(const std::shared_ptr<MapPoint>& mp) {
  std::lock_guard<std::mutex> lock(mutex_);
  map_points_.put(mp->id(), mp);
  raise_map_point_ids_past(mp->id());
}
void Map::raise_map_point_ids_past(uint32_t id) {
  if (id >= mp_id_first_ && id < mp_id_end_) raise_to(next_mp_id_, id + 1);
}
void Map::raise_keyframe_ids_past(uint32_t id) {
  if (id >= kf_id_first_ && id < kf_id_end_) raise_to(next_kf_id_, id + 1);
}
void Map::set_keyframe_id_space(uint32_t first, uint32_t end) {
  std::lock_guard<std::mutex> lock(mutex_);
  kf_id_first_ = first;
  kf_id_end_ = end;
  next_kf_id_ = next_id_in(keyframes_, first, end);
}
void Map::set_map_point_id_space(uint32_t first, uint32_t end) {
  std::lock_guard<std::mutex> lock(mutex_);
  mp_id_first_ = first;
  mp_id_end_ = end;
  next_mp_id_ = next_id_in(map_points_, first, end);
}
void Map::erase_keyframe(uint32_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.erase(id);
}
void Map::erase_map_point(uint32_t id) {
  std::lock_guard<std::mutex> lock(mutex_);
  map_points_.erase(id);
}
std::shared_ptr<KeyFrame> Map::keyframe(uint32_t id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto* kf = keyframes_.find(id);
  return kf ? *kf : nullptr;
}
std::shared_ptr<MapPoint> Map::map_point(uint32_t id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto* mp = map_points_.find(id);
  return mp ? *mp : nullptr;
}
std::vector<std::shared_ptr<MapPoint>> Map::map_points(const std::vector<uint32_t>& ids) const {
  std::vector<std::shared_ptr<MapPoint>> out(ids.size());
  // Slots and then the points' control blocks are fetched ahead: lookups of scattered ids
  // overlap their cache misses instead of waiting for each in turn.
  constexpr size_t kSlotAhead = 16, kPointAhead = 8;
  std::lock_guard<std::mutex> lock(mutex_);
  for (size_t i = 0; i < ids.size(); ++i) {
    if (i + kSlotAhead < ids.size() && ids[i + kSlotAhead] != kNoId)
      __builtin_prefetch(map_points_.slot_address(ids[i + kSlotAhead]));
    if (i + kPointAhead < ids.size() && ids[i + kPointAhead] != kNoId)
      if (const auto* ahead = map_points_.find(ids[i + kPointAhead])) __builtin_prefetch(ahead->get());
    if (ids[i] == kNoId) continue;
    if (const auto* mp = map_points_.find(ids[i])) out[i] = *mp;
  }
  return out;
}

std::vector<std::shared_ptr<KeyFrame>> Map::keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sorted_values(keyframes_);
}
std::vector<std::shared_ptr<MapPoint>> Map::map_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sorted_values(map_points_);
}
size_t Map::num_keyframes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_.size();
}
size_t Map::num_map_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return map_points_.size();
}
void Map::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.clear();
  map_points_.clear();
  reference_map_points_.clear();
}

void Map::rebuild(const std::vector<std::shared_ptr<KeyFrame>>& kfs,
                  const std::vector<std::shared_ptr<MapPoint>>& mps) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    keyframes_.clear();
    map_points_.clear();
    reference_map_points_.clear();
    keyframes_.reserve(kfs.size());
    map_points_.reserve(mps.size());
    for (const auto& kf : kfs) {
      keyframes_.put(kf->id(), kf);
      raise_keyframe_ids_past(kf->id());
    }
    for (const auto& mp : mps) {
      map_points_.put(mp->id(), mp);
      raise_map_point_ids_past(mp->id());
    }
  }
  for (const auto& mp : mps) mp->clear_observations();
  for (const auto& kf : kfs) {
    const auto ids = kf->map_point_ids();
    for (size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] == kNoId) continue;
      if (auto mp = map_point(ids[i]))
        mp->add_observation(kf->id(), static_cast<int>(i));
      else
        kf->erase_map_point_id(i);
    }
  }
  for (const auto& mp : mps) {
    const auto obs = mp->observations();
    if (!obs.empty() && !obs.count(mp->reference_kf_id())) mp->set_reference_kf_id(obs.begin()->first);
  }
  // Spanning tree: keep parents that are still present, re-derive the children.
  for (const auto& kf : kfs) {
    kf->clear_connections();
    kf->clear_children();
    if (kf->parent_id() != kNoId && !keyframe(kf->parent_id())) kf->set_parent(kNoId);
  }
  for (const auto& kf : kfs)
    if (kf->parent_id() != kNoId) keyframe(kf->parent_id())->add_child(kf->id());
  // Covisibility in id order (a keyframe without a parent gets one here).
  std::vector<std::shared_ptr<KeyFrame>> ordered = kfs;
  std::sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) { return a->id() < b->id(); });
  for (const auto& kf : ordered) kf->update_connections(*this);
}

void Map::adopt(Map& staged) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframes_.swap(staged.keyframes_);
  map_points_.swap(staged.map_points_);
  reference_map_points_.clear();
  keyframes_.for_each([&](uint32_t id, const std::shared_ptr<KeyFrame>&) { raise_keyframe_ids_past(id); });
  map_points_.for_each([&](uint32_t id, const std::shared_ptr<MapPoint>&) { raise_map_point_ids_past(id); });
}

void Map::set_reference_map_points(std::vector<std::shared_ptr<MapPoint>> mps) {
  std::lock_guard<std::mutex> lock(mutex_);
  reference_map_points_ = std::move(mps);
}
std::vector<std::shared_ptr<MapPoint>> Map::reference_map_points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return reference_map_points_;
}
void Map::reserve_ids(uint32_t next_kf_id, uint32_t next_mp_id) {
  raise_to(next_kf_id_, next_kf_id);
  raise_to(next_mp_id_, next_mp_id);
}

}  // namespace edge_slam
