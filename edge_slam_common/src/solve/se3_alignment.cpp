#include "edge_slam/solve/se3_alignment.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace edge_slam {
namespace {

AlignmentResult failure(const std::string& why) {
  AlignmentResult r;
  r.message = why;
  return r;
}

// Umeyama fit on the listed pairs; false when the b points are degenerate (collinear).
bool fit(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
         const std::vector<size_t>& idx, bool with_scale, Eigen::Matrix3d& R, Eigen::Vector3d& t,
         double& s) {
  const double n = static_cast<double>(idx.size());
  if (idx.size() < 3) return false;
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_b = Eigen::Vector3d::Zero();
  for (size_t i : idx) {
    mean_a += a[i];
    mean_b += b[i];
  }
  mean_a /= n;
  mean_b /= n;

  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // cross-covariance of a and b
  Eigen::Matrix3d cov_bb = Eigen::Matrix3d::Zero();
  double var_b = 0.0;
  for (size_t i : idx) {
    const Eigen::Vector3d da = a[i] - mean_a, db = b[i] - mean_b;
    cov += da * db.transpose();
    cov_bb += db * db.transpose();
    var_b += db.squaredNorm();
  }
  cov /= n;
  var_b /= n;
  if (!(var_b > 0.0)) return false;

  // The rotation is only determined when the points span at least a plane.
  const Eigen::JacobiSVD<Eigen::Matrix3d> spread(cov_bb / n);
  const Eigen::Vector3d spread_sv = spread.singularValues();
  if (!(spread_sv(1) > 1e-10 * spread_sv(0))) return false;

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sv = svd.singularValues();
  if (!(sv(1) > 1e-12 * std::max(sv(0), 1e-300))) return false;
  Eigen::Vector3d sign(1.0, 1.0, 1.0);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) sign(2) = -1.0;  // no reflections
  R = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  s = with_scale ? sv.dot(sign) / var_b : 1.0;
  if (!(s > 0.0) || !std::isfinite(s)) return false;
  t = mean_a - s * R * mean_b;
  return R.allFinite() && t.allFinite();
}

bool pair_is_finite(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a.allFinite() && b.allFinite();
}

AlignmentResult make_result(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double s) {
  AlignmentResult r;
  r.ok = true;
  r.T_ab.linear() = R;
  r.T_ab.translation() = t;
  r.scale = s;
  return r;
}

}  // namespace

AlignmentResult align_points(const std::vector<Eigen::Vector3d>& a,
                             const std::vector<Eigen::Vector3d>& b, bool with_scale) {
  if (a.size() != b.size()) return failure("point sets differ in size");
  if (a.size() < 3) return failure("fewer than 3 pairs");
  std::vector<size_t> idx(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    if (!pair_is_finite(a[i], b[i])) return failure("non-finite point");
    idx[i] = i;
  }
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  double s = 1.0;
  if (!fit(a, b, idx, with_scale, R, t, s)) return failure("degenerate (collinear) configuration");
  AlignmentResult r = make_result(R, t, s);
  r.inliers.assign(a.size(), true);
  r.num_inliers = static_cast<int>(a.size());
  r.message = "aligned " + std::to_string(a.size()) + " pairs";
  return r;
}

AlignmentResult ransac_align(const std::vector<Eigen::Vector3d>& a,
                             const std::vector<Eigen::Vector3d>& b,
                             const RansacAlignmentParams& p) {
  if (a.size() != b.size()) return failure("point sets differ in size");
  const size_t n = a.size();
  const bool per_pair = p.per_pair_thresholds.size() == n;

  std::vector<size_t> candidates;
  for (size_t i = 0; i < n; ++i) {
    if (pair_is_finite(a[i], b[i])) candidates.push_back(i);
  }
  const size_t min_required = static_cast<size_t>(std::max(3, p.min_inliers));
  if (candidates.size() < min_required) {
    return failure("too few finite pairs: " + std::to_string(candidates.size()));
  }

  auto threshold = [&](size_t i) { return per_pair ? p.per_pair_thresholds[i] : p.inlier_threshold; };
  // Classifies every pair against a model; returns the inlier count and their squared error.
  auto classify = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double s,
                      std::vector<bool>& inl, double& sq_error) {
    inl.assign(n, false);
    sq_error = 0.0;
    int count = 0;
    for (size_t i : candidates) {
      const double e = (a[i] - (s * (R * b[i]) + t)).norm();
      if (e <= threshold(i)) {
        inl[i] = true;
        sq_error += e * e;
        ++count;
      }
    }
    return count;
  };

  std::mt19937 rng(p.seed);
  std::uniform_int_distribution<size_t> pick(0, candidates.size() - 1);
  int best_count = 0;
  double best_error = std::numeric_limits<double>::infinity();
  Eigen::Matrix3d best_R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d best_t = Eigen::Vector3d::Zero();
  double best_s = 1.0;
  std::vector<bool> best_inliers, inl;

  int needed_iterations = p.max_iterations;
  for (int it = 0; it < needed_iterations; ++it) {
    std::vector<size_t> sample;
    while (sample.size() < 3) {
      const size_t c = candidates[pick(rng)];
      if (std::find(sample.begin(), sample.end(), c) == sample.end()) sample.push_back(c);
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    double s;
    if (!fit(a, b, sample, p.with_scale, R, t, s)) continue;
    double err;
    const int count = classify(R, t, s, inl, err);
    if (count > best_count || (count == best_count && err < best_error)) {
      best_count = count;
      best_error = err;
      best_R = R;
      best_t = t;
      best_s = s;
      best_inliers = inl;
      // Adaptive stop: iterations after which an all-inlier sample was drawn with probability p.
      const double w = static_cast<double>(count) / candidates.size();
      const double miss = 1.0 - w * w * w;
      if (miss <= 1e-12) {
        needed_iterations = std::min(needed_iterations, it + 1);
      } else {
        const double k = std::log(1.0 - p.probability) / std::log(miss);
        if (std::isfinite(k)) needed_iterations = std::min(p.max_iterations, std::max(it + 1, static_cast<int>(std::ceil(k))));
      }
    }
  }
  if (best_count < static_cast<int>(min_required)) {
    return failure("best model has only " + std::to_string(best_count) + " inliers");
  }

  for (int round = 0; round < p.refine_rounds; ++round) {
    std::vector<size_t> idx;
    for (size_t i = 0; i < n; ++i) {
      if (best_inliers[i]) idx.push_back(i);
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    double s, err;
    if (!fit(a, b, idx, p.with_scale, R, t, s)) break;
    const int count = classify(R, t, s, inl, err);
    if (count < best_count) break;  // the refit must not lose support
    const bool changed = inl != best_inliers;
    best_count = count;
    best_R = R;
    best_t = t;
    best_s = s;
    best_inliers = inl;
    if (!changed) break;
  }

  AlignmentResult r = make_result(best_R, best_t, best_s);
  r.inliers = best_inliers;
  r.num_inliers = best_count;
  r.message = "inliers " + std::to_string(best_count) + "/" + std::to_string(n);
  return r;
}

}  // namespace edge_slam
