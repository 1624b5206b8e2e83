#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "edge_slam/solve/se3_alignment.h"

using namespace edge_slam;

namespace {

Eigen::Isometry3d known_transform() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d(0.3, 1.0, -0.2).normalized())
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.6, -0.5, 0.6);  // ~1 m
  return T;
}

// b: random points; a = scale * T * b, except the first outlier_ratio of every 100 pairs,
// whose a is random.
void make_pairs(int n, double outlier_ratio, double scale, std::vector<Eigen::Vector3d>& a,
                std::vector<Eigen::Vector3d>& b, std::vector<bool>& planted_inlier) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(-2.0, 2.0);
  const Eigen::Isometry3d T = known_transform();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d pb(coord(rng), coord(rng), 1.0 + std::abs(coord(rng)));
    const bool inlier = (i % 100) >= outlier_ratio * 100;
    a.push_back(inlier ? Eigen::Vector3d(scale * (T.linear() * pb) + T.translation())
                       : Eigen::Vector3d(coord(rng), coord(rng), coord(rng)));
    b.push_back(pb);
    planted_inlier.push_back(inlier);
  }
}

}  // namespace

TEST(Se3Alignment, ExactRigidFit) {
  std::vector<Eigen::Vector3d> a, b;
  std::vector<bool> planted;
  make_pairs(20, 0.0, 1.0, a, b, planted);
  const AlignmentResult r = align_points(a, b);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_LT((r.T_ab.matrix() - known_transform().matrix()).norm(), 1e-9);
  EXPECT_DOUBLE_EQ(r.scale, 1.0);
}

TEST(Se3Alignment, ExactSimilarityFit) {
  std::vector<Eigen::Vector3d> a, b;
  std::vector<bool> planted;
  make_pairs(20, 0.0, 1.7, a, b, planted);
  const AlignmentResult r = align_points(a, b, true);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_NEAR(r.scale, 1.7, 1e-9);
  EXPECT_LT((r.T_ab.matrix() - known_transform().matrix()).norm(), 1e-9);
}

TEST(Se3Alignment, RansacRecoversTransformWithHalfOutliers) {
  std::vector<Eigen::Vector3d> a, b;
  std::vector<bool> planted;
  make_pairs(200, 0.5, 1.0, a, b, planted);
  RansacAlignmentParams p;
  p.inlier_threshold = 0.02;
  const AlignmentResult r = ransac_align(a, b, p);
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Isometry3d T = known_transform();
  const double rot_err = Eigen::AngleAxisd(T.linear().transpose() * r.T_ab.linear()).angle();
  const double t_err = (T.translation() - r.T_ab.translation()).norm();
  EXPECT_LT(rot_err, 1e-6);
  EXPECT_LT(t_err, 1e-6);
  int correct = 0;
  for (size_t i = 0; i < a.size(); ++i) correct += r.inliers[i] == planted[i];
  EXPECT_GE(correct, 198);  // a random outlier may land within 2 cm by chance
  EXPECT_GE(r.num_inliers, 100);
  std::printf("se3 ransac: rot_err %.2e rad, t_err %.2e m, %d inliers\n", rot_err, t_err, r.num_inliers);

  // Deterministic for a fixed seed.
  const AlignmentResult again = ransac_align(a, b, p);
  EXPECT_TRUE(again.T_ab.isApprox(r.T_ab, 0.0));
  EXPECT_EQ(again.inliers, r.inliers);
}

TEST(Se3Alignment, RansacWithScaleAndPerPairThresholds) {
  std::vector<Eigen::Vector3d> a, b;
  std::vector<bool> planted;
  make_pairs(100, 0.5, 0.8, a, b, planted);
  RansacAlignmentParams p;
  p.with_scale = true;
  p.per_pair_thresholds.assign(a.size(), 0.01);
  const AlignmentResult r = ransac_align(a, b, p);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_NEAR(r.scale, 0.8, 1e-6);
  ASSERT_TRUE(planted[99]);
  EXPECT_LT((r.map_b_to_a(b[99]) - a[99]).norm(), 1e-6);
}

TEST(Se3Alignment, DegenerateInputsFail) {
  std::vector<Eigen::Vector3d> a = {{0, 0, 0}, {1, 0, 0}}, b = a;
  EXPECT_FALSE(align_points(a, b).ok);
  a.push_back({2, 0, 0});  // collinear
  b = a;
  EXPECT_FALSE(align_points(a, b).ok);
  a.push_back({0, 1, std::nan("")});
  b = a;
  EXPECT_FALSE(align_points(a, b).ok);
  EXPECT_FALSE(align_points(a, {}).ok);

  std::vector<Eigen::Vector3d> ra, rb;
  std::vector<bool> planted;
  make_pairs(10, 0.0, 1.0, ra, rb, planted);
  RansacAlignmentParams p;
  p.min_inliers = 20;
  const AlignmentResult r = ransac_align(ra, rb, p);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
}
