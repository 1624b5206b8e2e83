// The second robot's path through the synthetic room (issue #16): same room, world frame and
// clock as robot 1, another smooth path, and views that robot 1 also has, but at other times,
// so that place recognition across the two robots has something to find.
//
// "Shares a view" is decided from the geometry and the tracker's own limits, not from tuned
// numbers: a pixel of view A is seen by view B when its surface point (exact ray casting)
// projects into B's image, is not hidden from B, is seen from directions less than 60 degrees
// apart (the tracker's kMinViewCos = 0.5) and at distances within the ORB pyramid's scale range
// (scale_factor^(num_levels - 1)). Two views overlap when most (more than half) of A's pixels
// are seen by B.
#include "edge_slam/feature/orb_params.h"
#include "edge_slam/sim/ray_cast.h"
#include "edge_slam/sim/scene.h"
#include "edge_slam/sim/synthetic_camera.h"
#include "edge_slam/sim/trajectory.h"
#include "edge_slam/sim/tum_sequence_writer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

using namespace edge_slam;

namespace {

double rotation_degrees(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

std::vector<Eigen::Isometry3d> sample(const Trajectory& traj, double fps) {
  std::vector<Eigen::Isometry3d> poses;
  const int n = static_cast<int>(std::floor(traj.duration() * fps + 1e-9)) + 1;
  for (int i = 0; i < n; ++i) poses.push_back(traj.pose_at(i / fps));
  return poses;
}

Trajectory robot1() {
  const SequenceOptions o;
  return Trajectory(o.camera_seed(), o.trajectory);
}

Trajectory robot2() {
  const SequenceOptions o = SequenceOptions::second_robot(42);
  return Trajectory(o.camera_seed(), o.trajectory);
}

class SecondRobot : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { scene_ = std::make_unique<Scene>(Scene::build(42, 4.0)); }  // geometry only
  static void TearDownTestSuite() { scene_.reset(); }

  // Fraction of view a's pixels (a 16 x 12 grid over the image) that view b sees too.
  static double shared_view(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    const PinholeCamera cam = synthetic_room_camera();
    const OrbParams orb;
    const double max_scale = std::pow(orb.scale_factor, orb.num_levels - 1);
    const Eigen::Isometry3d b_inv = b.inverse();
    int hits = 0, seen = 0;
    for (int row = 0; row < 12; ++row) {
      for (int col = 0; col < 16; ++col) {
        const double u = (col + 0.5) * cam.width / 16.0, v = (row + 0.5) * cam.height / 12.0;
        const Eigen::Vector3d ray_a = a.linear() * cam.unproject(u, v, 1.0);
        const double depth = hit_depth(*scene_, a.translation(), ray_a);
        if (!std::isfinite(depth)) continue;
        ++hits;
        const Eigen::Vector3d p = a.translation() + depth * ray_a;
        const Eigen::Vector3d p_b = b_inv * p;
        if (p_b.z() <= 0) continue;
        const Eigen::Vector2d px = cam.project(p_b);
        if (px.x() < 0 || px.x() >= cam.width || px.y() < 0 || px.y() >= cam.height) continue;
        const Eigen::Vector3d from_a = p - a.translation(), from_b = p - b.translation();
        const double dist_a = from_a.norm(), dist_b = from_b.norm();
        if (hit_depth(*scene_, b.translation(), from_b / dist_b) < dist_b - 0.01) continue;  // hidden
        if (from_a.dot(from_b) < 0.5 * dist_a * dist_b) continue;  // more than 60 degrees apart
        if (std::max(dist_a, dist_b) > max_scale * std::min(dist_a, dist_b)) continue;
        ++seen;
      }
    }
    return hits > 0 ? static_cast<double>(seen) / hits : 0.0;
  }

  static std::unique_ptr<Scene> scene_;
};
std::unique_ptr<Scene> SecondRobot::scene_;

constexpr double kFps = 30.0;

}  // namespace

TEST(SecondRobotOptions, SameRoomSameClockOwnCameraNoise) {
  const SequenceOptions one, two = SequenceOptions::second_robot(42);
  EXPECT_EQ(two.seed, one.seed) << "the same room";
  EXPECT_EQ(two.first_stamp, one.first_stamp) << "both robots start at once";
  EXPECT_EQ(two.fps, one.fps);
  EXPECT_EQ(sequence_frame_count(two), sequence_frame_count(one));
  EXPECT_NE(two.camera_seed(), one.camera_seed()) << "its own wobble and sensor noise";
  // Robot 1, the embedded default, keeps its path: no start phase, the look-away turn, seed 42.
  EXPECT_FALSE(one.path_seed.has_value());
  EXPECT_EQ(one.camera_seed(), 42u);
  EXPECT_EQ(one.trajectory.start_phase, 0.0);
  EXPECT_GT(one.trajectory.turn_degrees, 0.0);
}

TEST_F(SecondRobot, ClosedSmoothPathWithoutFastTurn) {
  const Trajectory traj = robot2();
  EXPECT_NEAR(traj.duration(), 30.0, 1e-12);
  const Eigen::Isometry3d a = traj.pose_at(0), b = traj.pose_at(traj.duration());
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-9);
  EXPECT_LT(rotation_degrees(a, b), 1e-6);

  // Trackable everywhere: robot 1's bounds outside its turn (translation, rotation per frame).
  double max_step = 0, max_rot = 0, max_bend = 0;
  const std::vector<Eigen::Isometry3d> poses = sample(traj, kFps);
  for (size_t i = 1; i < poses.size(); ++i) {
    max_step = std::max(max_step, (poses[i].translation() - poses[i - 1].translation()).norm());
    max_rot = std::max(max_rot, rotation_degrees(poses[i - 1], poses[i]));
    if (i + 1 < poses.size())
      max_bend = std::max(max_bend, (poses[i + 1].translation() - 2 * poses[i].translation() +
                                     poses[i - 1].translation()).norm());
  }
  EXPECT_LT(max_step, 0.03);
  EXPECT_LT(max_rot, 2.0);

  // Continuous and smooth: sampled 10x finer, the largest step shrinks ~10x (a jump would not
  // shrink) and the largest second difference ~100x (a kink in the velocity would shrink 10x).
  double fine_step = 0, fine_rot = 0, fine_bend = 0;
  const std::vector<Eigen::Isometry3d> fine = sample(traj, 10 * kFps);
  for (size_t i = 1; i < fine.size(); ++i) {
    fine_step = std::max(fine_step, (fine[i].translation() - fine[i - 1].translation()).norm());
    fine_rot = std::max(fine_rot, rotation_degrees(fine[i - 1], fine[i]));
    if (i + 1 < fine.size())
      fine_bend = std::max(fine_bend, (fine[i + 1].translation() - 2 * fine[i].translation() +
                                       fine[i - 1].translation()).norm());
  }
  EXPECT_LT(fine_step, 0.2 * max_step);
  EXPECT_LT(fine_rot, 0.2 * max_rot);
  EXPECT_LT(fine_bend, 0.05 * max_bend);
}

TEST_F(SecondRobot, StaysClearOfFurnitureAndLooksAtTheRoom) {
  // Robot 1's criteria (test_synth_trajectory), on robot 2's path.
  std::vector<double> centre_depths;
  for (const Eigen::Isometry3d& T : sample(robot2(), kFps)) {
    const Eigen::Vector3d p = T.translation();
    EXPECT_TRUE(scene_->room.contains(p, -0.8)) << p.transpose();
    for (const AlignedBox& box : scene_->boxes) EXPECT_FALSE(box.contains(p, 0.8)) << p.transpose();
    const Eigen::Vector3d forward = T.linear().col(2);
    EXPECT_LT(forward.z(), 0.25) << "looking up at the ceiling";
    EXPECT_GT(forward.z(), -0.6) << "staring at the floor";
    centre_depths.push_back(hit_depth(*scene_, p, forward));
  }
  std::sort(centre_depths.begin(), centre_depths.end());
  EXPECT_GT(centre_depths.front(), 0.8);
  const double median = centre_depths[centre_depths.size() / 2];
  EXPECT_GT(median, 1.5);
  EXPECT_LT(median, 4.5);
}

TEST_F(SecondRobot, DiffersFromRobot1AtEveryInstant) {
  // Both play at once: at the same stamp the two robots never look at the same place, so what
  // they share can only be found by place recognition, not by simultaneous co-observation.
  const Trajectory one = robot1(), two = robot2();
  EXPECT_EQ(shared_view(two.pose_at(0), one.pose_at(0)), 0.0) << "opposite sides of the room";
  EXPECT_EQ(shared_view(one.pose_at(0), two.pose_at(0)), 0.0);
  double most = 0;
  for (int i = 0; i <= 300; ++i) {
    const double t = i / 10.0, s = shared_view(two.pose_at(t), one.pose_at(t));
    EXPECT_LT(s, 0.5) << "t=" << t;
    most = std::max(most, s);
  }
  std::printf("at the same stamp the robots share at most %.2f of robot 2's view\n", most);
}

TEST_F(SecondRobot, SeesWhatRobot1SeesAtOtherTimes) {
  const Trajectory one = robot1(), two = robot2();
  const std::vector<Eigen::Isometry3d> ones = sample(one, 10.0);  // robot 1 every 0.1 s
  auto best_match = [&](const Eigen::Isometry3d& view, double& share) {
    share = -1;
    double when = -1;
    for (size_t k = 0; k < ones.size(); ++k) {
      const double s = shared_view(view, ones[k]);
      if (s > share) share = s, when = k / 10.0;
    }
    return when;
  };
  // Robot 2 walks the same loop direction looking outwards: every place it passes, robot 1
  // has a view of it, about half a loop away in time.
  double least_share = 1, least_gap = 1e9;
  for (int i = 0; i <= 30; ++i) {
    const double t = i;
    double share = 0;
    const double when = best_match(two.pose_at(t), share);
    EXPECT_GT(share, 0.5) << "robot 2 at t=" << t << " s: no view of robot 1 shares most of it";
    least_share = std::min(least_share, share);
    least_gap = std::min(least_gap, std::abs(when - t));
  }
  // (Never at the same stamp: DiffersFromRobot1AtEveryInstant.)
  std::printf("every second of robot 2: best robot 1 view shares >= %.2f, >= %.1f s apart\n",
              least_share, least_gap);

  // Part-way through, in both directions: robot 2's first view is robot 1's some seconds in
  // (robot 1 can recognise robot 2's start), and robot 1's first view comes up for robot 2
  // within its loop (robot 2 can recognise robot 1's start).
  double share = 0;
  const double robot1_reaches_robot2_start = best_match(two.pose_at(0), share);
  EXPECT_GT(share, 0.5);
  EXPECT_GT(robot1_reaches_robot2_start, 0.0);
  EXPECT_LT(robot1_reaches_robot2_start, one.duration());
  double best_share = -1, robot2_reaches_robot1_start = -1;
  for (int i = 0; i <= 300; ++i) {
    const double t = i / 10.0, s = shared_view(one.pose_at(0), two.pose_at(t));
    if (s > best_share) best_share = s, robot2_reaches_robot1_start = t;
  }
  EXPECT_GT(best_share, 0.5);
  EXPECT_GT(robot2_reaches_robot1_start, 0.0);
  EXPECT_LT(robot2_reaches_robot1_start, two.duration());
  std::printf("robot 2's start view: robot 1 at %.1f s (share %.2f); robot 1's start view: robot 2 at %.1f s (share %.2f)\n",
              robot1_reaches_robot2_start, share, robot2_reaches_robot1_start, best_share);
}
