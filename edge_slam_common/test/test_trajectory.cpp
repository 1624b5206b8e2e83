#include <gtest/gtest.h>

#include <cstdio>

#include "edge_slam/io/trajectory_io.h"
#include "edge_slam/util/timing_stats.h"

using namespace edge_slam;

TEST(Trajectory, TumRoundTrip) {
  std::vector<std::pair<double, Eigen::Isometry3d>> poses;
  for (int i = 0; i < 5; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(0.1 * i, -0.2 * i, 1.0 + i);
    poses.emplace_back(1305031102.175304 + i / 30.0, T);
  }
  const std::string path = ::testing::TempDir() + "traj_roundtrip.txt";
  write_tum_trajectory(path, poses);
  const auto back = read_tum_trajectory(path);
  ASSERT_EQ(back.size(), poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    EXPECT_NEAR(back[i].first, poses[i].first, 1e-6);
    EXPECT_TRUE(back[i].second.isApprox(poses[i].second, 1e-6));
  }
  std::remove(path.c_str());
  EXPECT_THROW(read_tum_trajectory("/nonexistent/traj.txt"), std::runtime_error);
}

TEST(Trajectory, TimingStats) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  const TimingStats s = summarize_times(v);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.median, 50.5);
  EXPECT_DOUBLE_EQ(s.p95, 95);
  EXPECT_DOUBLE_EQ(s.max, 100);
  EXPECT_EQ(summarize_times({}).count, 0u);
}
