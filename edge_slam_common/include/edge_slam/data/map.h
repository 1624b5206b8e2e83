// The map: keyframes and map points indexed by id in flat hash maps (util/flat_id_map.h: one
// cache miss per lookup; tracking resolves ~10^4 ids a frame), so that clearing it and
// rebuilding it from lists (a Local-Map update) is linear in their number. Also holds the
// id allocators and the "reference" map points (the tracker's local map, for drawing).
#pragma once
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map_point.h"
#include "edge_slam/util/flat_id_map.h"

namespace edge_slam {

class Map {
 public:
  void add_keyframe(const std::shared_ptr<KeyFrame>& kf);
  void add_map_point(const std::shared_ptr<MapPoint>& mp);
  void erase_keyframe(uint32_t id);
  void erase_map_point(uint32_t id);

  std::shared_ptr<KeyFrame> keyframe(uint32_t id) const;    // null if absent
  std::shared_ptr<MapPoint> map_point(uint32_t id) const;   // null if absent
  // Resolves many ids under one lock (null where absent): out[i] = map_point(ids[i]).
  std::vector<std::shared_ptr<MapPoint>> map_points(const std::vector<uint32_t>& ids) const;
  std::vector<std::shared_ptr<KeyFrame>> keyframes() const;   // sorted by id
  std::vector<std::shared_ptr<MapPoint>> map_points() const;  // sorted by id
  size_t num_keyframes() const;
  size_t num_map_points() const;

  void clear();
  // Replaces the content with the given keyframes and map points and re-links them in
  // time linear in keyframes + observations (plus sorting the keyframes by id, so the
  // spanning tree does not depend on the list order): map point observations are rebuilt from the keyframes' map point ids
  // (ids of absent points are dropped), covisibility is recomputed, spanning tree parents
  // are kept when the parent is present (recomputed otherwise) and children re-derived.
  // Callers hold update_mutex() so that tracking never sees a half-built map.
  void rebuild(const std::vector<std::shared_ptr<KeyFrame>>& kfs,
               const std::vector<std::shared_ptr<MapPoint>>& mps);

  // Takes `staged`'s keyframes and map points in O(1) (hash maps swapped; `staged` gets the old
  // content, freed when the caller drops it) and moves the id allocators past the new ids: a
  // Local-Map update is built and linked off-line in a staged map, and tracking pauses only for
  // this. The caller holds update_mutex(); `staged` is private to the caller.
  void adopt(Map& staged);

  void set_reference_map_points(std::vector<std::shared_ptr<MapPoint>> mps);
  std::vector<std::shared_ptr<MapPoint>> reference_map_points() const;

  uint32_t new_keyframe_id() { return next_kf_id_++; }
  uint32_t new_map_point_id() { return next_mp_id_++; }
  // Map points this map creates get ids in [first, end); ids outside it (points created by
  // the other side of the split) never move this map's allocator. Default: every id.
  void set_map_point_id_space(uint32_t first, uint32_t end);
  // The same for KeyFrames: a mobile's Local-Map holds other robots' KeyFrames after a merge
  // (util/robot_ids.h), and those must not move its own allocator.
  void set_keyframe_id_space(uint32_t first, uint32_t end);
  // Makes future ids larger than any id already used (e.g. ids coming from another map).
  void reserve_ids(uint32_t next_kf_id, uint32_t next_mp_id);
  // The ids the allocators would hand out next, without taking them (map persistence).
  uint32_t next_keyframe_id() const { return next_kf_id_; }
  uint32_t next_map_point_id() const { return next_mp_id_; }

  // Held by a module while it changes the map as a whole (like ORB-SLAM2's
  // mMutexMapUpdate), so that tracking never sees a half-applied update.
  std::mutex& update_mutex() const { return update_mutex_; }

 private:
  mutable std::mutex mutex_;
  mutable std::mutex update_mutex_;
  FlatIdMap<std::shared_ptr<KeyFrame>> keyframes_;
  FlatIdMap<std::shared_ptr<MapPoint>> map_points_;
  std::vector<std::shared_ptr<MapPoint>> reference_map_points_;
  std::atomic<uint32_t> next_kf_id_{0};
  std::atomic<uint32_t> next_mp_id_{0};
  uint32_t mp_id_first_ = 0, mp_id_end_ = kNoId;
  uint32_t kf_id_first_ = 0, kf_id_end_ = kNoId;
  void raise_map_point_ids_past(uint32_t id);
  void raise_keyframe_ids_past(uint32_t id);
};

}  // namespace edge_slam
