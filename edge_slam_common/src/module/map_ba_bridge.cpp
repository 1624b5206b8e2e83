#include "edge_slam/module/map_ba_bridge.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

#include "edge_slam/data/map_edit.h"

namespace edge_slam {
namespace {

BaObservation make_observation(const KeyFrame& kf, uint32_t mp_id, size_t idx) {
  const FrameFeatures& f = kf.features();
  BaObservation o;
  o.keyframe_id = kf.id();
  o.point_id = mp_id;
  o.pixel = {f.keys_un[idx].pt.x, f.keys_un[idx].pt.y};
  o.right_x = f.right_x[idx];
  o.inv_sigma2 = f.pyramid->inv_level_sigma2[f.keys_un[idx].octave];
  return o;
}

// Adds the observations of `mp` made by keyframes in `slot` (id -> included).
// Returns the number of observations added.
size_t add_point(BundleAdjustmentProblem& p, const MapPoint& mp,
                 const std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>>& kfs) {
  const size_t before = p.observations.size();
  BaPoint bp;
  bp.id = mp.id();
  bp.position = mp.position();
  p.points.push_back(bp);
  for (const auto& [kf_id, idx] : mp.observations()) {
    const auto it = kfs.find(kf_id);
    if (it == kfs.end() || idx < 0 || static_cast<size_t>(idx) >= it->second->features().size()) continue;
    if (it->second->map_point_id(idx) != mp.id()) continue;
    p.observations.push_back(make_observation(*it->second, mp.id(), idx));
  }
  return p.observations.size() - before;
}

}  // namespace

BundleAdjustmentProblem build_local_ba_problem(const Map& map, const KeyFrame& kf_in, const LocalBaWindow& window) {
  BundleAdjustmentProblem p;
  const auto kf = map.keyframe(kf_in.id());
  if (!kf || kf->is_bad()) return p;
  p.camera = kf->features().camera;

  std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>> local{{kf->id(), kf}};
  for (uint32_t id : kf->ordered_neighbours()) {  // strongest covisibility first
    if (window.max_free_keyframes > 0 && local.size() >= window.max_free_keyframes) break;
    auto nb = map.keyframe(id);
    if (nb && !nb->is_bad()) local.emplace(id, std::move(nb));
  }
  std::unordered_map<uint32_t, std::shared_ptr<MapPoint>> points;
  for (const auto& [id, k] : local)
    for (auto& mp : k->map_points(map))
      if (mp) points.emplace(mp->id(), std::move(mp));

  // Fixed keyframes: the other observers of the window's points, most observations first.
  std::unordered_map<uint32_t, int> window_observations;
  for (const auto& [id, mp] : points)
    mp->for_each_observation([&](uint32_t obs_kf, int) {
      if (!local.count(obs_kf)) ++window_observations[obs_kf];
    });
  std::vector<std::pair<int, uint32_t>> by_count;  // (-count, id): most first, ties by id
  by_count.reserve(window_observations.size());
  for (const auto& [id, n] : window_observations) by_count.emplace_back(-n, id);
  std::sort(by_count.begin(), by_count.end());
  std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>> all = local;
  size_t fixed = 0;
  for (const auto& [neg_count, id] : by_count) {
    if (window.max_fixed_keyframes > 0 && fixed >= window.max_fixed_keyframes) break;
    auto other = map.keyframe(id);
    if (other && !other->is_bad()) {
      all.emplace(id, std::move(other));
      ++fixed;
    }
  }
  for (const auto& [id, k] : all) {
    BaKeyFrame b;
    b.id = id;
    b.T_cw = k->T_cw();
    b.fixed = !local.count(id) || k->parent_id() == kNoId;
    p.keyframes.push_back(b);
  }
  for (const auto& [id, mp] : points) add_point(p, *mp, all);
  return p;
}

BundleAdjustmentProblem build_full_ba_problem(const Map& map, const std::function<bool(uint32_t kf_id)>& in_map) {
  BundleAdjustmentProblem p;
  std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>> all;
  for (auto& kf : map.keyframes()) {
    if (kf->is_bad() || (in_map && !in_map(kf->id()))) continue;
    if (p.keyframes.empty()) p.camera = kf->features().camera;
    BaKeyFrame b;
    b.id = kf->id();
    b.T_cw = kf->T_cw();
    b.fixed = kf->parent_id() == kNoId;
    p.keyframes.push_back(b);
    all.emplace(kf->id(), std::move(kf));
  }
  // The gauge: a spanning tree's root is held; a map whose root has gone holds its oldest KeyFrame.
  if (!p.keyframes.empty() && std::none_of(p.keyframes.begin(), p.keyframes.end(), [](const BaKeyFrame& b) { return b.fixed; }))
    std::min_element(p.keyframes.begin(), p.keyframes.end(), [](const BaKeyFrame& a, const BaKeyFrame& b) { return a.id < b.id; })
        ->fixed = true;
  for (const auto& mp : map.map_points())
    if (!mp->is_bad() && add_point(p, *mp, all) == 0) p.points.pop_back();
  return p;
}

BaApplyStats apply_ba_result(Map& map, const BundleAdjustmentProblem& problem,
                             const BundleAdjustmentResult& result, bool erase_outliers) {
  BaApplyStats s;
  if (!result.ok) return s;
  if (erase_outliers) {
    for (size_t i : result.outlier_observations) {
      const BaObservation& o = problem.observations[i];
      const auto kf = map.keyframe(o.keyframe_id);
      const auto mp = map.map_point(o.point_id);
      if (!kf || !mp || mp->is_bad()) continue;
      if (mp->index_in(kf->id()) < 0) continue;
      erase_observation(map, kf, mp);
      ++s.erased_observations;
    }
  }
  for (const BaKeyFrame& b : result.keyframes) {
    if (b.fixed) continue;
    const auto kf = map.keyframe(b.id);
    if (!kf || kf->is_bad()) continue;
    kf->set_pose(b.T_cw);
    ++s.keyframes;
  }
  for (const BaPoint& b : result.points) {
    const auto mp = map.map_point(b.id);
    if (!mp || mp->is_bad() || !b.position.allFinite()) continue;
    mp->set_position(b.position);
    mp->update_normal_and_depth(map);
    ++s.points;
  }
  return s;
}

}  // namespace edge_slam
