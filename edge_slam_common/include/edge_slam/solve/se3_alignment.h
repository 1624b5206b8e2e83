// Closed-form alignment of two corresponding 3D point sets (Umeyama's SVD solution of Horn's
// absolute orientation problem), rigid or with scale, and a RANSAC wrapper over 3-point minimal
// samples. Loop closing uses it to estimate the SE(3) (RGB-D) transform between two keyframes
// from matched map points.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace edge_slam {

struct AlignmentResult {
  bool ok = false;
  std::string message;
  // Maps b into a: a_i ~= scale * T_ab.linear() * b_i + T_ab.translation().
  Eigen::Isometry3d T_ab = Eigen::Isometry3d::Identity();
  double scale = 1.0;  // 1 unless estimated with_scale
  std::vector<bool> inliers;  // per correspondence; all true for align_points on success
  int num_inliers = 0;

  Eigen::Vector3d map_b_to_a(const Eigen::Vector3d& b) const {
    return scale * (T_ab.linear() * b) + T_ab.translation();
  }
};

// Least-squares fit over all pairs (a[i], b[i]). Fails on size mismatch, fewer than 3 pairs,
// non-finite points or (near-)collinear configurations.
AlignmentResult align_points(const std::vector<Eigen::Vector3d>& a,
                             const std::vector<Eigen::Vector3d>& b, bool with_scale = false);

struct RansacAlignmentParams {
  bool with_scale = false;
  // Pair i is an inlier when |a_i - map_b_to_a(b_i)| <= its threshold (metres): per_pair_thresholds[i]
  // when that vector has one entry per pair, else inlier_threshold.
  double inlier_threshold = 0.05;
  std::vector<double> per_pair_thresholds;
  int max_iterations = 300;
  double probability = 0.99;  // stops early once a model this likely to be all-inlier was drawn
  int min_inliers = 6;        // ok=false below this many inliers
  uint32_t seed = 42;         // samples are drawn deterministically from this seed
  int refine_rounds = 3;      // refits on the inliers, then re-classifies, this many times
};

// RANSAC over minimal 3-pair samples, then least-squares refinement on the inliers. Non-finite
// pairs are never inliers. ok=false (with a message) when no model reaches min_inliers.
AlignmentResult ransac_align(const std::vector<Eigen::Vector3d>& a,
                             const std::vector<Eigen::Vector3d>& b,
                             const RansacAlignmentParams& params = {});

}  // namespace edge_slam
