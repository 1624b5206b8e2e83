#include "edge_slam/sim/synthetic_camera.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "edge_slam/optimize/full_bundle_adjustment.h"
#include "edge_slam/optimize/local_bundle_adjustment.h"

using namespace edge_slam;

namespace {

PinholeCamera make_camera() { return synthetic_room_camera(30.0); }

Eigen::Isometry3d small_motion(std::mt19937& rng, double metres, double degrees) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(degrees * M_PI / 180.0, axis).toRotationMatrix();
  T.translation() = metres * dir;
  return T;
}

double centre_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

struct SyntheticMap {
  BundleAdjustmentProblem truth;      // exact poses and points
  BundleAdjustmentProblem perturbed;  // what the optimiser gets
  std::set<size_t> planted_outliers;
};

// Keyframes on a short sideways track, all looking down +z at points 1-5 m away; every point is
// observed by every keyframe it projects into, alternately with mono and stereo-projected terms.
SyntheticMap make_map(int num_keyframes, int num_points, int num_fixed, double noise_px,
                      int num_outliers, unsigned seed) {
  SyntheticMap m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const PinholeCamera cam = make_camera();
  m.truth.camera = cam;

  for (int k = 0; k < num_keyframes; ++k) {
    BaKeyFrame kf;
    kf.id = 10 + static_cast<uint32_t>(k);
    Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();
    T_wc.linear() = Eigen::AngleAxisd(0.03 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    T_wc.translation() = Eigen::Vector3d(0.15 * k, 0.02 * k, 0.0);
    kf.T_cw = T_wc.inverse();
    kf.fixed = k < num_fixed;
    m.truth.keyframes.push_back(kf);
  }
  const Eigen::Isometry3d T_wc_mid = m.truth.keyframes[num_keyframes / 2].T_cw.inverse();
  for (int i = 0; i < num_points; ++i) {
    BaPoint p;
    p.id = 1000 + static_cast<uint32_t>(i);
    p.position = T_wc_mid * cam.unproject(cam.width * unit(rng), cam.height * unit(rng), 1.0 + 4.0 * unit(rng));
    m.truth.points.push_back(p);
  }
  for (const BaKeyFrame& kf : m.truth.keyframes) {
    for (const BaPoint& p : m.truth.points) {
      const Eigen::Vector3d Xc = kf.T_cw * p.position;
      const Eigen::Vector2d uv = cam.project(Xc);
      if (Xc.z() <= 0 || uv.x() < 0 || uv.y() < 0 || uv.x() >= cam.width || uv.y() >= cam.height) continue;
      BaObservation o;
      o.keyframe_id = kf.id;
      o.point_id = p.id;
      o.pixel = uv + Eigen::Vector2d(noise(rng), noise(rng));
      if (p.id % 2 == 0) o.right_x = uv.x() - cam.bf / Xc.z() + noise(rng);
      m.truth.observations.push_back(o);
    }
  }
  m.perturbed = m.truth;
  std::vector<size_t> order(m.truth.observations.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  for (int j = 0; j < num_outliers; ++j) {
    BaObservation& o = m.perturbed.observations[order[static_cast<size_t>(j)]];
    o.pixel += Eigen::Vector2d(40.0 + 100.0 * unit(rng), -40.0 - 100.0 * unit(rng));
    if (o.right_x >= 0) o.right_x = o.pixel.x() - 5.0;
    m.planted_outliers.insert(order[static_cast<size_t>(j)]);
  }
  for (BaKeyFrame& kf : m.perturbed.keyframes) {
    if (!kf.fixed) kf.T_cw = small_motion(rng, 0.02, 1.0) * kf.T_cw;
  }
  for (BaPoint& p : m.perturbed.points) {
    std::normal_distribution<double> n(0.0, 1.0);
    p.position += 0.02 * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  }
  return m;
}

}  // namespace

TEST(LocalBundleAdjustment, ReducesErrorKeepsFixedAndReportsOutliers) {
  SyntheticMap m = make_map(5, 300, 2, 0.5, 15, 21);
  const BundleAdjustmentResult r = run_local_bundle_adjustment(m.perturbed);
  ASSERT_TRUE(r.ok) << r.message;
  ASSERT_EQ(r.keyframes.size(), 5u);
  ASSERT_EQ(r.points.size(), 300u);

  EXPECT_LT(r.final_cost, 0.1 * r.initial_cost);
  // With 0.5 px noise, chi2 per observation averages ~2-3 (dof) * 0.25.
  const double per_obs = r.final_cost / (m.perturbed.observations.size() - r.outlier_observations.size());
  EXPECT_LT(per_obs, 1.0);

  for (size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(r.keyframes[k].T_cw.matrix() == m.perturbed.keyframes[k].T_cw.matrix());
  }
  double worst_pose = 0.0, worst_before = 0.0;
  for (size_t k = 2; k < 5; ++k) {
    worst_pose = std::max(worst_pose, centre_error(r.keyframes[k].T_cw, m.truth.keyframes[k].T_cw));
    worst_before = std::max(worst_before, centre_error(m.perturbed.keyframes[k].T_cw, m.truth.keyframes[k].T_cw));
  }
  EXPECT_LT(worst_pose, 0.005);
  double point_rms = 0.0;
  for (size_t i = 0; i < r.points.size(); ++i) point_rms += (r.points[i].position - m.truth.points[i].position).squaredNorm();
  point_rms = std::sqrt(point_rms / r.points.size());

  const std::set<size_t> reported(r.outlier_observations.begin(), r.outlier_observations.end());
  for (size_t i : m.planted_outliers) EXPECT_TRUE(reported.count(i)) << "planted outlier " << i;
  EXPECT_LE(reported.size(), m.planted_outliers.size() + 3);  // a few noise tails at most

  std::printf("local BA: %zu obs, cost %.1f -> %.1f (%.2f per obs), worst KF centre err %.4f m (was %.4f), "
              "point rms %.4f m, %zu outliers reported (%zu planted), %d iterations\n",
              m.perturbed.observations.size(), r.initial_cost, r.final_cost, per_obs, worst_pose,
              worst_before, point_rms, reported.size(), m.planted_outliers.size(), r.iterations);
}

TEST(LocalBundleAdjustment, AbortFlagStopsEarly) {
  SyntheticMap m = make_map(4, 100, 1, 0.5, 0, 4);
  std::atomic<bool> abort{true};
  LocalBaOptions options;
  options.abort = &abort;
  const BundleAdjustmentResult r = run_local_bundle_adjustment(m.perturbed, options);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.aborted);
  EXPECT_LE(r.iterations, 1);
}

TEST(LocalBundleAdjustment, DegenerateProblemsFail) {
  SyntheticMap m = make_map(3, 50, 3, 0.0, 0, 5);  // every keyframe fixed
  BundleAdjustmentResult r = run_local_bundle_adjustment(m.perturbed);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.message.empty());
  EXPECT_EQ(r.keyframes.size(), 3u);

  m = make_map(3, 50, 1, 0.0, 0, 5);
  BundleAdjustmentProblem empty = m.perturbed;
  empty.observations.clear();
  r = run_local_bundle_adjustment(empty);
  EXPECT_FALSE(r.ok);

  BundleAdjustmentProblem nan_pose = m.perturbed;
  nan_pose.keyframes[1].T_cw.translation().x() = std::nan("");
  EXPECT_FALSE(run_local_bundle_adjustment(nan_pose).ok);
}

TEST(LocalBundleAdjustment, NanPointIsReportedNotPropagated) {
  SyntheticMap m = make_map(3, 60, 1, 0.0, 0, 6);
  m.perturbed.points[3].position.y() = std::nan("");
  const BundleAdjustmentResult r = run_local_bundle_adjustment(m.perturbed);
  ASSERT_TRUE(r.ok) << r.message;
  for (size_t i = 0; i < m.perturbed.observations.size(); ++i) {
    if (m.perturbed.observations[i].point_id == m.perturbed.points[3].id) {
      EXPECT_TRUE(std::count(r.outlier_observations.begin(), r.outlier_observations.end(), i));
    }
  }
  for (const BaKeyFrame& kf : r.keyframes) EXPECT_TRUE(kf.T_cw.matrix().allFinite());
}

TEST(FullBundleAdjustment, FixesSmallestIdWhenNoneFixed) {
  SyntheticMap m = make_map(4, 200, 0, 0.3, 0, 8);
  m.perturbed.keyframes[0].T_cw = m.truth.keyframes[0].T_cw;  // the gauge keyframe is exact
  const BundleAdjustmentResult r = run_full_bundle_adjustment(m.perturbed, 20);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(r.keyframes[0].T_cw.matrix() == m.perturbed.keyframes[0].T_cw.matrix());
  EXPECT_LT(r.final_cost, 0.1 * r.initial_cost);
  for (size_t k = 1; k < 4; ++k) EXPECT_LT(centre_error(r.keyframes[k].T_cw, m.truth.keyframes[k].T_cw), 0.005);
}

TEST(LocalBundleAdjustment, NoiseFreeMapConvergesToTruth) {
  SyntheticMap m = make_map(5, 300, 2, 0.0, 15, 22);
  const BundleAdjustmentResult r = run_local_bundle_adjustment(m.perturbed);
  ASSERT_TRUE(r.ok) << r.message;
  double worst_point = 0.0;
  for (size_t i = 0; i < r.points.size(); ++i) {
    worst_point = std::max(worst_point, (r.points[i].position - m.truth.points[i].position).norm());
  }
  double worst_pose = 0.0;
  for (size_t k = 0; k < 5; ++k) worst_pose = std::max(worst_pose, centre_error(r.keyframes[k].T_cw, m.truth.keyframes[k].T_cw));
  EXPECT_LT(worst_pose, 1e-6);
  EXPECT_LT(worst_point, 1e-5);
  std::printf("noise-free local BA: worst KF centre err %.2e m, worst point err %.2e m, %zu outliers\n",
              worst_pose, worst_point, r.outlier_observations.size());
}
