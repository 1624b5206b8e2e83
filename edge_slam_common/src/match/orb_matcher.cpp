#include "edge_slam/match/orb_matcher.h"

#include <cmath>
#include <limits>

#include "edge_slam/match/rotation_histogram.h"

namespace edge_slam {
namespace {

// A keypoint already matched to a map point that some keyframe observes is left alone.
bool already_matched(const Frame& frame, size_t idx) {
  const auto& mp = frame.map_points[idx];
  return mp && mp->num_observations() > 0;
}

// Search window factor: a point seen nearly head-on is localised more reliably.
float radius_for_view_cos(float view_cos) { return view_cos > 0.998f ? 2.5f : 4.0f; }

void reject_inconsistent(const RotationHistogram& hist, Frame& frame, int& matches) {
  for (int idx : hist.inconsistent()) {
    frame.map_points[idx] = nullptr;
    --matches;
  }
}

}  // namespace

bool project_into_frame(const Frame& frame, const std::shared_ptr<MapPoint>& mp, float min_view_cos,
                        ProjectedPoint& out) {
  const FrameFeatures& f = frame.feat();
  const MapPoint::Geometry g = mp->geometry();
  const Eigen::Vector3d p_c = frame.T_cw() * g.position;
  if (!(p_c.z() > 0)) return false;
  const Eigen::Vector2d uv = f.camera.project(p_c);
  if (!f.bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y()))) return false;
  // Viewing ray from the camera centre: R^T * p_c (the centre is -R^T t).
  const Eigen::Vector3d ray = frame.T_cw().linear().transpose() * p_c;
  const double dist = ray.norm();
  if (dist < g.min_distance || dist > g.max_distance) return false;
  const double n_norm = g.normal.norm();
  const double view_cos = n_norm > 0 ? ray.dot(g.normal) / (dist * n_norm) : 1.0;
  if (view_cos < min_view_cos) return false;
  out.mp = mp;
  out.u = static_cast<float>(uv.x());
  out.v = static_cast<float>(uv.y());
  out.u_right = static_cast<float>(uv.x() - f.camera.bf / p_c.z());
  out.level = f.pyramid->predict_level(g.max_level0_distance, dist);
  out.view_cos = static_cast<float>(view_cos);
  return true;
}

int OrbMatcher::search_by_projection(Frame& frame, const std::vector<ProjectedPoint>& points,
                                     float th) const {
  const FrameFeatures& f = frame.feat();
  int matches = 0;
  std::vector<size_t> candidates;
  constexpr size_t kPrefetchAhead = 8;  // points: enough to cover a cache miss
  for (size_t k = 0; k < points.size(); ++k) {
    if (k + kPrefetchAhead < points.size() && points[k + kPrefetchAhead].mp)
      points[k + kPrefetchAhead].mp->prefetch_descriptor();
    const ProjectedPoint& p = points[k];
    if (!p.mp || p.mp->is_bad()) continue;
    const float r = th * radius_for_view_cos(p.view_cos) * f.pyramid->scale_factors[p.level];
    frame.features_in_area(p.u, p.v, r, p.level - 1, p.level, candidates);
    if (candidates.empty()) continue;
    const Descriptor d = p.mp->descriptor();
    int best = std::numeric_limits<int>::max(), second = best;
    int best_level = -1, second_level = -1;
    long best_idx = -1;
    for (size_t idx : candidates) {
      if (already_matched(frame, idx)) continue;
      if (f.right_x[idx] > 0 && std::fabs(p.u_right - f.right_x[idx]) > r) continue;
      const int dist = descriptor_distance(d.data(), f.descriptor(idx));
      if (dist < best) {
        second = best;
        second_level = best_level;
        best = dist;
        best_level = f.keys_un[idx].octave;
        best_idx = static_cast<long>(idx);
      } else if (dist < second) {
        second = dist;
        second_level = f.keys_un[idx].octave;
      }
    }
    if (best_idx < 0 || best > kThHigh) continue;
    if (best_level == second_level && best > nn_ratio_ * second) continue;
    frame.map_points[best_idx] = p.mp;
    frame.outliers[best_idx] = false;
    ++matches;
  }
  return matches;
}

int OrbMatcher::search_by_projection(Frame& frame, const Frame& last, float th) const {
  const FrameFeatures& f = frame.feat();
  const FrameFeatures& lf = last.feat();
  const Eigen::Isometry3d& T_cw = frame.T_cw();
  // Current camera centre expressed in the last camera frame: moving forward means the
  // points appear larger (finer levels become coarser), so restrict the level range.
  const Eigen::Vector3d t_lc = last.T_cw() * frame.camera_center();
  const double baseline = f.camera.baseline();
  const bool forward = t_lc.z() > baseline;
  const bool backward = -t_lc.z() > baseline;

  RotationHistogram hist;
  int matches = 0;
  std::vector<size_t> candidates;
  for (size_t i = 0; i < last.map_points.size(); ++i) {
    const auto& mp = last.map_points[i];
    if (!mp || last.outliers[i] || mp->is_bad()) continue;
    const Eigen::Vector3d p_c = T_cw * mp->position();
    if (!(p_c.z() > 0)) continue;
    const Eigen::Vector2d uv = f.camera.project(p_c);
    const float u = static_cast<float>(uv.x()), v = static_cast<float>(uv.y());
    if (!f.bounds.contains(u, v)) continue;
    const int level = lf.keys_un[i].octave;
    const float r = th * f.pyramid->scale_factors[level];
    if (forward)
      frame.features_in_area(u, v, r, level, -1, candidates);
    else if (backward)
      frame.features_in_area(u, v, r, 0, level, candidates);
    else
      frame.features_in_area(u, v, r, level - 1, level + 1, candidates);
    if (candidates.empty()) continue;
    const float u_right = static_cast<float>(u - f.camera.bf / p_c.z());
    const Descriptor d = mp->descriptor();
    int best = std::numeric_limits<int>::max();
    long best_idx = -1;
    for (size_t idx : candidates) {
      if (already_matched(frame, idx)) continue;
      if (f.right_x[idx] > 0 && std::fabs(u_right - f.right_x[idx]) > r) continue;
      const int dist = descriptor_distance(d.data(), f.descriptor(idx));
      if (dist < best) {
        best = dist;
        best_idx = static_cast<long>(idx);
      }
    }
    if (best_idx < 0 || best > kThHigh) continue;
    frame.map_points[best_idx] = mp;
    frame.outliers[best_idx] = false;
    ++matches;
    if (check_orientation_) hist.add(lf.keys[i].angle, f.keys[best_idx].angle, static_cast<int>(best_idx));
  }
  if (check_orientation_) reject_inconsistent(hist, frame, matches);
  return matches;
}

int OrbMatcher::search_by_projection(Frame& frame, const KeyFrame& kf,
                                     const std::vector<std::shared_ptr<MapPoint>>& kf_points,
                                     const std::unordered_set<uint32_t>& already_found, float th,
                                     int max_distance) const {
  const FrameFeatures& f = frame.feat();
  const Eigen::Vector3d center = frame.camera_center();
  RotationHistogram hist;
  int matches = 0;
  std::vector<size_t> candidates;
  for (size_t i = 0; i < kf_points.size(); ++i) {
    const auto& mp = kf_points[i];
    if (!mp || mp->is_bad() || already_found.count(mp->id())) continue;
    const Eigen::Vector3d p_w = mp->position();
    const Eigen::Vector3d p_c = frame.T_cw() * p_w;
    if (!(p_c.z() > 0)) continue;
    const Eigen::Vector2d uv = f.camera.project(p_c);
    const float u = static_cast<float>(uv.x()), v = static_cast<float>(uv.y());
    if (!f.bounds.contains(u, v)) continue;
    const double dist3 = (p_w - center).norm();
    if (dist3 < mp->min_distance() || dist3 > mp->max_distance()) continue;
    const int level = mp->predict_level(dist3, *f.pyramid);
    const float r = th * f.pyramid->scale_factors[level];
    frame.features_in_area(u, v, r, level - 1, level + 1, candidates);
    const Descriptor d = mp->descriptor();
    int best = std::numeric_limits<int>::max();
    long best_idx = -1;
    for (size_t idx : candidates) {
      if (frame.map_points[idx]) continue;
      const int dist = descriptor_distance(d.data(), f.descriptor(idx));
      if (dist < best) {
        best = dist;
        best_idx = static_cast<long>(idx);
      }
    }
    if (best_idx < 0 || best > max_distance) continue;
    frame.map_points[best_idx] = mp;
    frame.outliers[best_idx] = false;
    ++matches;
    if (check_orientation_) hist.add(kf.features().keys[i].angle, f.keys[best_idx].angle, static_cast<int>(best_idx));
  }
  if (check_orientation_) reject_inconsistent(hist, frame, matches);
  return matches;
}

int OrbMatcher::search_by_bow(const KeyFrame& kf, const std::vector<std::shared_ptr<MapPoint>>& kf_points,
                              Frame& frame) const {
  const FrameFeatures& kff = kf.features();
  const FrameFeatures& f = frame.feat();
  const FeatureVector& fv_kf = kf.feature_vector();
  const FeatureVector& fv_f = frame.feature_vector();
  RotationHistogram hist;
  int matches = 0;
  auto it_kf = fv_kf.begin();
  auto it_f = fv_f.begin();
  while (it_kf != fv_kf.end() && it_f != fv_f.end()) {
    if (it_kf->first < it_f->first) {
      it_kf = fv_kf.lower_bound(it_f->first);
      continue;
    }
    if (it_f->first < it_kf->first) {
      it_f = fv_f.lower_bound(it_kf->first);
      continue;
    }
    for (uint32_t i_kf : it_kf->second) {
      if (i_kf >= kf_points.size()) continue;
      const auto& mp = kf_points[i_kf];
      if (!mp || mp->is_bad()) continue;
      const uint8_t* d = kff.descriptor(i_kf);
      int best = std::numeric_limits<int>::max(), second = best;
      long best_idx = -1;
      for (uint32_t i_f : it_f->second) {
        if (i_f >= f.size() || frame.map_points[i_f]) continue;
        const int dist = descriptor_distance(d, f.descriptor(i_f));
        if (dist < best) {
          second = best;
          best = dist;
          best_idx = i_f;
        } else if (dist < second) {
          second = dist;
        }
      }
      if (best_idx < 0 || best > kThLow || static_cast<float>(best) >= nn_ratio_ * second) continue;
      frame.map_points[best_idx] = mp;
      frame.outliers[best_idx] = false;
      ++matches;
      if (check_orientation_) hist.add(kff.keys[i_kf].angle, f.keys[best_idx].angle, static_cast<int>(best_idx));
    }
    ++it_kf;
    ++it_f;
  }
  if (check_orientation_) reject_inconsistent(hist, frame, matches);
  return matches;
}

}  // namespace edge_slam
