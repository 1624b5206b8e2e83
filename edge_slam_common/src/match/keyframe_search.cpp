#include "edge_slam/match/keyframe_search.h"

#include <cmath>
#include <limits>
#include <unordered_set>

#include "edge_slam/data/map_edit.h"
#include "edge_slam/match/orb_matcher.h"
#include "edge_slam/match/rotation_histogram.h"

namespace edge_slam {
namespace {

constexpr float kMinViewCos = 0.5f;
constexpr double kChi2Mono = 5.991, kChi2Stereo = 7.815, kChi2Epipolar = 3.84;

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d intrinsics(const PinholeCamera& c) {
  Eigen::Matrix3d K;
  K << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1;
  return K;
}

bool has_good_point(const KeyFrame& kf, const Map& map, size_t i) {
  const uint32_t id = kf.map_point_id(i);
  if (id == kNoId) return false;
  const auto mp = map.map_point(id);
  return mp && !mp->is_bad();
}

// Walks the nodes shared by two feature vectors.
template <class F>
void for_each_shared_node(const FeatureVector& a, const FeatureVector& b, F&& f) {
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) {
      ia = a.lower_bound(ib->first);
    } else if (ib->first < ia->first) {
      ib = b.lower_bound(ia->first);
    } else {
      f(ia->second, ib->second);
      ++ia;
      ++ib;
    }
  }
}

}  // namespace

Eigen::Matrix3d fundamental_matrix(const KeyFrame& kf1, const KeyFrame& kf2) {
  const Eigen::Isometry3d T_12 = kf1.T_cw() * kf2.T_wc();
  const Eigen::Matrix3d K1inv = intrinsics(kf1.features().camera).inverse();
  const Eigen::Matrix3d K2inv = intrinsics(kf2.features().camera).inverse();
  return K1inv.transpose() * skew(T_12.translation()) * T_12.linear() * K2inv;
}

std::vector<std::pair<size_t, size_t>> search_for_triangulation(const KeyFrame& kf1, const KeyFrame& kf2,
                                                                const Map& map,
                                                                const Eigen::Matrix3d& F12) {
  const FrameFeatures& f1 = kf1.features();
  const FrameFeatures& f2 = kf2.features();
  // Epipole: kf1's centre seen in kf2.
  const Eigen::Vector3d c1_in_2 = kf2.T_cw() * kf1.camera_center();
  const Eigen::Vector2d epipole = f2.camera.project(c1_in_2);
  std::vector<bool> used2(f2.size(), false);
  std::vector<long> match12(f1.size(), -1);
  RotationHistogram hist;

  for_each_shared_node(kf1.feature_vector(), kf2.feature_vector(),
                       [&](const std::vector<uint32_t>& idx1, const std::vector<uint32_t>& idx2) {
    for (uint32_t i1 : idx1) {
      if (i1 >= f1.size() || has_good_point(kf1, map, i1)) continue;
      const bool stereo1 = f1.right_x[i1] >= 0;
      const cv::KeyPoint& k1 = f1.keys_un[i1];
      const Eigen::Vector3d line = F12.transpose() * Eigen::Vector3d(k1.pt.x, k1.pt.y, 1.0);
      const double line_norm2 = line.x() * line.x() + line.y() * line.y();
      if (!(line_norm2 > 0)) continue;
      int best = OrbMatcher::kThLow + 1;
      long best_i2 = -1;
      for (uint32_t i2 : idx2) {
        if (i2 >= f2.size() || used2[i2] || has_good_point(kf2, map, i2)) continue;
        const int d = descriptor_distance(f1.descriptor(i1), f2.descriptor(i2));
        if (d >= best) continue;
        const cv::KeyPoint& k2 = f2.keys_un[i2];
        const bool stereo2 = f2.right_x[i2] >= 0;
        if (!stereo1 && !stereo2) {
          const double ex = epipole.x() - k2.pt.x, ey = epipole.y() - k2.pt.y;
          const double s = f2.pyramid->scale_factors[k2.octave];
          if (ex * ex + ey * ey < 100 * s * s) continue;
        }
        const double num = line.x() * k2.pt.x + line.y() * k2.pt.y + line.z();
        if (num * num / line_norm2 >= kChi2Epipolar * f2.pyramid->level_sigma2[k2.octave]) continue;
        best = d;
        best_i2 = i2;
      }
      if (best_i2 < 0) continue;
      used2[best_i2] = true;
      match12[i1] = best_i2;
      hist.add(k1.angle, f2.keys_un[best_i2].angle, static_cast<int>(i1));
    }
  });
  for (int i1 : hist.inconsistent()) match12[i1] = -1;
  std::vector<std::pair<size_t, size_t>> out;
  for (size_t i1 = 0; i1 < match12.size(); ++i1)
    if (match12[i1] >= 0) out.emplace_back(i1, static_cast<size_t>(match12[i1]));
  return out;
}

int search_by_bow(const KeyFrame& kf1, const KeyFrame& kf2, const Map& map,
                  std::vector<std::shared_ptr<MapPoint>>& matches12, float nn_ratio) {
  const FrameFeatures& f1 = kf1.features();
  const FrameFeatures& f2 = kf2.features();
  const auto points1 = kf1.map_points(map);
  const auto points2 = kf2.map_points(map);
  matches12.assign(f1.size(), nullptr);
  std::vector<bool> used2(f2.size(), false);
  RotationHistogram hist;
  int n = 0;
  for_each_shared_node(kf1.feature_vector(), kf2.feature_vector(),
                       [&](const std::vector<uint32_t>& idx1, const std::vector<uint32_t>& idx2) {
    for (uint32_t i1 : idx1) {
      if (i1 >= points1.size() || !points1[i1]) continue;
      int best = std::numeric_limits<int>::max(), second = best;
      long best_i2 = -1;
      for (uint32_t i2 : idx2) {
        if (i2 >= points2.size() || used2[i2] || !points2[i2]) continue;
        const int d = descriptor_distance(f1.descriptor(i1), f2.descriptor(i2));
        if (d < best) {
          second = best;
          best = d;
          best_i2 = i2;
        } else if (d < second) {
          second = d;
        }
      }
      if (best_i2 < 0 || best > OrbMatcher::kThLow || static_cast<float>(best) >= nn_ratio * second) continue;
      matches12[i1] = points2[best_i2];
      used2[best_i2] = true;
      ++n;
      hist.add(f1.keys_un[i1].angle, f2.keys_un[best_i2].angle, static_cast<int>(i1));
    }
  });
  for (int i1 : hist.inconsistent()) {
    matches12[i1] = nullptr;
    --n;
  }
  return n;
}

namespace {
// A point predicted visible in a keyframe with pose T_cw.
struct Projection {
  double u, v, u_right;
  int level;
  double radius_scale;
};

bool project(const KeyFrame& kf, const Eigen::Isometry3d& T_cw, const MapPoint& mp, Projection& out) {
  const FrameFeatures& f = kf.features();
  const Eigen::Vector3d p_w = mp.position();
  const Eigen::Vector3d p_c = T_cw * p_w;
  if (!(p_c.z() > 0)) return false;
  const Eigen::Vector2d uv = f.camera.project(p_c);
  if (!f.bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y()))) return false;
  const Eigen::Vector3d ray = p_w - T_cw.inverse().translation();
  const double dist = ray.norm();
  if (dist < mp.min_distance() || dist > mp.max_distance()) return false;
  const Eigen::Vector3d n = mp.normal();
  if (n.norm() > 0 && ray.dot(n) < kMinViewCos * dist * n.norm()) return false;
  out.u = uv.x();
  out.v = uv.y();
  out.u_right = uv.x() - f.camera.bf / p_c.z();
  out.level = mp.predict_level(dist, *f.pyramid);
  out.radius_scale = f.pyramid->scale_factors[out.level];
  return true;
}
}  // namespace

int search_by_projection(const KeyFrame& kf, const Eigen::Isometry3d& T_cw,
                         const std::vector<std::shared_ptr<MapPoint>>& points,
                         std::vector<std::shared_ptr<MapPoint>>& matched, float th) {
  const FrameFeatures& f = kf.features();
  matched.resize(f.size());
  std::unordered_set<uint32_t> already;
  for (const auto& mp : matched)
    if (mp) already.insert(mp->id());
  int n = 0;
  std::vector<size_t> candidates;
  for (const auto& mp : points) {
    if (!mp || mp->is_bad() || already.count(mp->id())) continue;
    Projection p;
    if (!project(kf, T_cw, *mp, p)) continue;
    kf.features_in_area(static_cast<float>(p.u), static_cast<float>(p.v), static_cast<float>(th * p.radius_scale), -1,
                        -1, candidates);
    const Descriptor d = mp->descriptor();
    int best = std::numeric_limits<int>::max();
    long best_idx = -1;
    for (size_t idx : candidates) {
      if (matched[idx]) continue;
      const int level = f.keys_un[idx].octave;
      if (level < p.level - 1 || level > p.level) continue;
      const int dist = descriptor_distance(d.data(), f.descriptor(idx));
      if (dist < best) {
        best = dist;
        best_idx = static_cast<long>(idx);
      }
    }
    if (best_idx < 0 || best > OrbMatcher::kThLow) continue;
    matched[best_idx] = mp;
    already.insert(mp->id());
    ++n;
  }
  return n;
}

namespace {

// The keypoint of kf that mp projects onto and matches best (ORB-SLAM2's Fuse test), or -1;
// reads kf and mp only, so it may run without the map's update mutex.
long best_fusion_keypoint(const KeyFrame& kf, const Eigen::Isometry3d& T_cw, const MapPoint& mp,
                          const FuseOptions& options, std::vector<size_t>& candidates) {
  if (mp.is_bad() || mp.index_in(kf.id()) >= 0) return -1;
  const FrameFeatures& f = kf.features();
  Projection p;
  if (!project(kf, T_cw, mp, p)) return -1;
  kf.features_in_area(static_cast<float>(p.u), static_cast<float>(p.v), static_cast<float>(options.th * p.radius_scale),
                      -1, -1, candidates);
  const Descriptor d = mp.descriptor();
  int best = std::numeric_limits<int>::max();
  long best_idx = -1;
  for (size_t idx : candidates) {
    const cv::KeyPoint& kp = f.keys_un[idx];
    if (kp.octave < p.level - 1 || kp.octave > p.level) continue;
    if (options.check_reprojection) {
      const double ex = p.u - kp.pt.x, ey = p.v - kp.pt.y;
      const double inv_s2 = f.pyramid->inv_level_sigma2[kp.octave];
      if (f.right_x[idx] >= 0) {
        const double er = p.u_right - f.right_x[idx];
        if ((ex * ex + ey * ey + er * er) * inv_s2 > kChi2Stereo) continue;
      } else if ((ex * ex + ey * ey) * inv_s2 > kChi2Mono) {
        continue;
      }
    }
    const int dist = descriptor_distance(d.data(), f.descriptor(idx));
    if (dist < best) {
      best = dist;
      best_idx = static_cast<long>(idx);
    }
  }
  return best_idx >= 0 && best <= OrbMatcher::kThLow ? best_idx : -1;
}

// Fuses mp with keypoint idx of kf on the map as it is now: nothing when mp went bad or is
// already in kf, else merged with the keypoint's point or added as its observation.
bool apply_fusion(Map& map, const std::shared_ptr<KeyFrame>& kf, const std::shared_ptr<MapPoint>& mp, size_t idx,
                  const FuseOptions& options) {
  if (mp->is_bad() || mp->index_in(kf->id()) >= 0) return false;
  const uint32_t existing_id = kf->map_point_id(idx);
  const auto existing = existing_id == kNoId ? nullptr : map.map_point(existing_id);
  if (existing && !existing->is_bad()) {
    if (existing == mp) return false;
    if (options.projected_wins || mp->num_observations() >= existing->num_observations())
      replace_map_point(map, existing, mp);
    else
      replace_map_point(map, mp, existing);
  } else {
    add_observation(kf, idx, mp);
  }
  return true;
}

}  // namespace

int fuse(Map& map, const std::shared_ptr<KeyFrame>& kf, const Eigen::Isometry3d& T_cw,
         const std::vector<std::shared_ptr<MapPoint>>& points, const FuseOptions& options) {
  int n = 0;
  std::vector<size_t> candidates;
  for (const auto& mp : points) {
    if (!mp) continue;
    const long idx = best_fusion_keypoint(*kf, T_cw, *mp, options, candidates);
    if (idx >= 0 && apply_fusion(map, kf, mp, static_cast<size_t>(idx), options)) ++n;
  }
  return n;
}

FusionMatches find_fusion_matches(const std::shared_ptr<KeyFrame>& kf, const Eigen::Isometry3d& T_cw,
                                  const std::vector<std::shared_ptr<MapPoint>>& points, const FuseOptions& options) {
  FusionMatches matches;
  matches.kf = kf;
  std::vector<size_t> candidates;
  for (const auto& mp : points) {
    if (!mp) continue;
    const long idx = best_fusion_keypoint(*kf, T_cw, *mp, options, candidates);
    if (idx >= 0) matches.pairs.emplace_back(mp, static_cast<size_t>(idx));
  }
  return matches;
}

int apply_fusion_matches(Map& map, const FusionMatches& matches, const FuseOptions& options) {
  int n = 0;
  if (!matches.kf || matches.kf->is_bad()) return 0;
  for (const auto& [mp, idx] : matches.pairs)
    if (apply_fusion(map, matches.kf, mp, idx, options)) ++n;
  return n;
}

}  // namespace edge_slam
