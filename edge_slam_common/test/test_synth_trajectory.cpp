// The synthetic trajectory: a closed loop, one fast in-place turn, moderate motion elsewhere,
// never inside furniture, always looking at walls/furniture at a sensible distance.
#include "edge_slam/sim/ray_cast.h"
#include "edge_slam/sim/scene.h"
#include "edge_slam/sim/trajectory.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace edge_slam;

namespace {

constexpr double kFps = 30.0;

double rotation_degrees(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

double heading_degrees(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d forward = T.linear().col(2);
  return std::atan2(forward.y(), forward.x()) * 180.0 / M_PI;
}

std::vector<Eigen::Isometry3d> sample(const Trajectory& traj) {
  std::vector<Eigen::Isometry3d> poses;
  const int n = static_cast<int>(std::floor(traj.duration() * kFps + 1e-9)) + 1;
  for (int i = 0; i < n; ++i) poses.push_back(traj.pose_at(i / kFps));
  return poses;
}

}  // namespace

TEST(SynthTrajectory, EndsExactlyAtItsStartPose) {
  const Trajectory traj(42);
  EXPECT_NEAR(traj.duration(), 30.0, 1e-12);
  const Eigen::Isometry3d a = traj.pose_at(0), b = traj.pose_at(traj.duration());
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-9);
  EXPECT_LT(rotation_degrees(a, b), 1e-6);
  // Yet it really travels: the far side of the loop is metres away.
  EXPECT_GT((traj.pose_at(15.0).translation() - a.translation()).norm(), 3.0);
}

TEST(SynthTrajectory, OneFastTurnAndModerateMotionElsewhere) {
  const Trajectory traj(42);
  const std::vector<Eigen::Isometry3d> poses = sample(traj);
  ASSERT_EQ(poses.size(), 901u);
  std::vector<int> fast_frames;
  double max_rot_elsewhere = 0, max_step = 0;
  for (size_t i = 1; i < poses.size(); ++i) {
    const double rot = rotation_degrees(poses[i - 1], poses[i]);
    const double step = (poses[i].translation() - poses[i - 1].translation()).norm();
    max_step = std::max(max_step, step);
    if (rot > 2.0) fast_frames.push_back(static_cast<int>(i));
    else max_rot_elsewhere = std::max(max_rot_elsewhere, rot);
  }
  EXPECT_LT(max_step, 0.03) << "translation per frame";
  EXPECT_LT(max_rot_elsewhere, 2.0);
  ASSERT_FALSE(fast_frames.empty());
  // The fast frames form one contiguous run inside the turn window.
  EXPECT_EQ(fast_frames.back() - fast_frames.front() + 1, static_cast<int>(fast_frames.size()));
  EXPECT_GE(fast_frames.front() / kFps, traj.turn_start());
  EXPECT_LE((fast_frames.back() - 1) / kFps, traj.turn_end());
  // About 90 degrees of yaw within ~0.4 s, turned (nearly) in place.
  const Eigen::Isometry3d before = traj.pose_at(traj.turn_start()), after = traj.pose_at(traj.turn_end());
  double yaw = heading_degrees(after) - heading_degrees(before);
  yaw = std::remainder(yaw, 360.0);
  EXPECT_NEAR(std::abs(yaw), 90.0, 12.0);
  EXPECT_LT((after.translation() - before.translation()).norm(), 0.08);
  // Then it turns slowly back, standing still, to the view it had before the turn (walls
  // mapped already), so that relocalization can succeed: same place, same heading up to the
  // hand-held wobble.
  const Eigen::Isometry3d back = traj.pose_at(traj.look_away_end());
  EXPECT_LT(std::abs(std::remainder(heading_degrees(back) - heading_degrees(before), 360.0)), 4.0);
  EXPECT_LT((back.translation() - before.translation()).norm(), 0.15);  // hand-held sway goes on
}

TEST(SynthTrajectory, StaysClearOfFurnitureAndLooksAtTheRoom) {
  const Scene scene = Scene::build(42, 4.0);  // coarse textures: geometry only matters here
  const Trajectory traj(42);
  std::vector<double> centre_depths;
  for (const Eigen::Isometry3d& T : sample(traj)) {
    const Eigen::Vector3d p = T.translation();
    EXPECT_TRUE(scene.room.contains(p, -0.8)) << p.transpose();
    for (const AlignedBox& box : scene.boxes) EXPECT_FALSE(box.contains(p, 0.8)) << p.transpose();
    const Eigen::Vector3d forward = T.linear().col(2);
    EXPECT_LT(forward.z(), 0.25) << "looking up at the ceiling";
    EXPECT_GT(forward.z(), -0.6) << "staring at the floor";
    centre_depths.push_back(hit_depth(scene, p, forward));
  }
  std::sort(centre_depths.begin(), centre_depths.end());
  EXPECT_GT(centre_depths.front(), 0.8);
  const double median = centre_depths[centre_depths.size() / 2];
  EXPECT_GT(median, 1.5);
  EXPECT_LT(median, 4.5);
}

TEST(SynthTrajectory, LongVariantLoopsManyTimesAndCloses) {
  TrajectoryOptions options;
  options.loops = 24;
  const Trajectory traj(7, options);
  EXPECT_NEAR(traj.duration(), 720.0, 1e-9);
  const Eigen::Isometry3d a = traj.pose_at(0), b = traj.pose_at(traj.duration());
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-9);
  EXPECT_LT(rotation_degrees(a, b), 1e-6);
}
