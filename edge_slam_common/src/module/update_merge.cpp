#include "edge_slam/module/update_merge.h"

#include <Eigen/Geometry>
#include <atomic>
#include <unordered_map>
#include <unordered_set>

namespace edge_slam {
namespace {

using Corrections = std::unordered_map<uint32_t, Eigen::Isometry3d>;  // KeyFrame id -> x_new = C x_old

// The correction a kept KeyFrame follows: its parent's, else its strongest covisible's among
// those already corrected (update KeyFrames, or kept ones earlier in id order), else `fallback`.
Eigen::Isometry3d correction_for(const KeyFrame& kf, const Corrections& known, const Eigen::Isometry3d& fallback) {
  if (const auto it = known.find(kf.parent_id()); it != known.end()) return it->second;
  const Eigen::Isometry3d* best = nullptr;
  int best_w = 0;
  for (const auto& [id, w] : kf.connection_weights()) {
    const auto it = known.find(id);
    if (it != known.end() && w > best_w) {
      best = &it->second;
      best_w = w;
    }
  }
  return best ? *best : fallback;
}

}  // namespace

MergeResult merge_update(Map& live, Map& staged, KeyFrameDatabase* database) {
  MergeResult out;
  const std::vector<std::shared_ptr<KeyFrame>> update_kfs = staged.keyframes();  // by id
  const std::vector<std::shared_ptr<MapPoint>> update_points = staged.map_points();
  std::unordered_set<uint32_t> in_update;
  for (const auto& kf : update_kfs) in_update.insert(kf->id());

  // 1. What the update did to the KeyFrames the Local-Map also had: the corrections to follow.
  Corrections correction;
  Eigen::Isometry3d fallback = Eigen::Isometry3d::Identity();  // at the newest such KeyFrame
  for (const auto& kf : update_kfs)
    if (const auto old = live.keyframe(kf->id())) {
      correction[kf->id()] = kf->T_wc() * old->T_cw();
      fallback = correction[kf->id()];
    }

  // 2. The live copies of the update's KeyFrames leave: their observations go with them. A point
  //    nobody observes then, and that the update does not bring back, is one the edge culled or
  //    fused into another: it leaves too (kept, such points would pile up without bound).
  std::unordered_set<uint32_t> update_point_ids;
  update_point_ids.reserve(update_points.size());
  for (const auto& mp : update_points) update_point_ids.insert(mp->id());
  for (const auto& kf : update_kfs) {
    const auto old = live.keyframe(kf->id());
    if (!old) continue;
    const std::vector<uint32_t> ids = old->map_point_ids();
    for (uint32_t id : ids) {
      if (id == kNoId) continue;
      const auto mp = live.map_point(id);
      if (!mp) continue;
      mp->erase_observation(kf->id());
      if (mp->num_observations() == 0 && !update_point_ids.count(id)) {
        mp->set_bad();  // a frame still holding it (the last one) lets go of it
        live.erase_map_point(id);
        ++out.points_dropped;
      }
    }
    if (database) database->erase(old);
    live.erase_keyframe(kf->id());
    ++out.keyframes_replaced;
  }

  // 3. The update's points replace their live versions, taking over what kept KeyFrames observe.
  for (const auto& mp : update_points) {
    if (const auto old = live.map_point(mp->id())) {
      for (const auto& [kf_id, idx] : old->observations())
        if (!in_update.count(kf_id) && mp->index_in(kf_id) < 0) mp->add_observation(kf_id, idx);
      live.erase_map_point(mp->id());
      ++out.points_replaced;
    } else {
      ++out.points_added;
    }
    live.add_map_point(mp);
  }

  // 4. The update's KeyFrames.
  for (const auto& kf : update_kfs) {
    live.add_keyframe(kf);
    if (database && kf->has_bow()) database->add(kf);
  }
  out.keyframes_added = update_kfs.size() - out.keyframes_replaced;

  // 5. Kept KeyFrames follow the correction around them; each of their points not in the update
  //    moves once, with the first kept KeyFrame (in id order, so usually the one that made it).
  //    Tracking is paused: one batch lookup per KeyFrame and one lock per point keep it short.
  static std::atomic<uint64_t> passes{0};
  const uint64_t pass = ++passes;
  for (const auto& kf : live.keyframes()) {
    if (in_update.count(kf->id())) continue;
    const Eigen::Isometry3d C = correction_for(*kf, correction, fallback);
    correction[kf->id()] = C;
    kf->set_pose((C * kf->T_wc()).inverse());
    ++out.keyframes_kept;
    for (const auto& mp : live.map_points(kf->map_point_ids()))
      if (mp && !update_point_ids.count(mp->id()) && mp->transform_once(C, pass)) ++out.points_moved;
    if (in_update.count(kf->parent_id()))
      if (const auto parent = live.keyframe(kf->parent_id())) parent->add_child(kf->id());
  }

  // 6. Covisibility of the update's KeyFrames with everything now in the map (mirrored to the kept).
  for (const auto& kf : update_kfs) kf->update_connections(live);
  staged.clear();
  return out;
}

}  // namespace edge_slam
