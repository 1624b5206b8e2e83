// The synthetic hand-held camera path: loops around the room centre on an ellipse at ~1.4 m
// height, looking outwards at the walls and furniture, with smooth periodic hand-held wobble.
// Once, at the middle of the sequence, the walker stops and turns fast in place (~90 degrees
// of yaw in ~0.4 s); the rest of the yaw budget is spread over the loop so that the path ends
// exactly at its start pose (every wobble term makes an integer number of cycles).
#pragma once
#include <Eigen/Geometry>

#include <cstdint>

namespace edge_slam {

struct TrajectoryOptions {
  double loop_seconds = 30.0;   // one loop around the room
  int loops = 1;
  double turn_degrees = 90.0;   // the single fast in-place turn (0 disables it)
  double turn_seconds = 0.4;    // its duration
  double height = 1.4;          // mean camera height above the floor (m)
  double radius_x = 2.0, radius_y = 1.2;  // loop ellipse half-axes (m)
};

class Trajectory {
 public:
  explicit Trajectory(uint64_t seed, const TrajectoryOptions& options = TrajectoryOptions());

  // Pose of the camera optical frame (x right, y down, z forward) in the world (z up).
  // t in [0, duration()]; pose_at(duration()) == pose_at(0).
  Eigen::Isometry3d pose_at(double t) const;

  double duration() const { return duration_; }
  double turn_start() const { return turn_centre_ - 0.5 * options_.turn_seconds; }
  double turn_end() const { return turn_centre_ + 0.5 * options_.turn_seconds; }
  const TrajectoryOptions& options() const { return options_; }

 private:
  double loop_angle(double t) const;  // position angle on the ellipse, 0 .. 2*pi*loops
  double turn_yaw(double t) const;    // 0 before the fast turn, turn angle after it
  double wobble(double t, int term) const;

  TrajectoryOptions options_;
  double duration_ = 0;
  double turn_centre_ = 0;
  double pause_half_width_ = 0;  // the walker slows to a stop around the turn
  double phases_[16] = {};
};

}  // namespace edge_slam
