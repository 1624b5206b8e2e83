// The synthetic hand-held camera path: loops around the room centre on an ellipse at ~1.4 m
// height, looking outwards at the walls and furniture, with smooth periodic hand-held wobble.
// Once, at the middle of the sequence, the walker stops and looks away fast in place (~90
// degrees of yaw in ~0.4 s), holds, then turns slowly back to the heading of the loop: the
// fast turn can make tracking fail, and the way back faces already-mapped walls so that
// relocalization has something to find. The path ends exactly at its start pose (every
// wobble term makes an integer number of cycles; the look-away nets zero yaw).
// A second robot (issue #16) walks the same kind of loop in the same room and world frame,
// from another point of it (start_phase), optionally on another ellipse and height and without
// the look-away (turn_degrees = 0): SequenceOptions::second_robot() in tum_sequence_writer.h.
#pragma once
#include <Eigen/Geometry>

#include <cstdint>

namespace edge_slam {

struct TrajectoryOptions {
  double loop_seconds = 30.0;   // one loop around the room
  int loops = 1;
  double turn_degrees = 90.0;   // the single fast in-place turn (0 disables it)
  double turn_seconds = 0.4;    // its duration
  double hold_seconds = 0.3;    // looking away
  double return_seconds = 4.0;  // the slow turn back (< 2 degrees per frame at 30 fps)
  double height = 1.4;          // mean camera height above the floor (m)
  double radius_x = 2.0, radius_y = 1.2;  // loop ellipse half-axes (m)
  // Where on the loop the path starts and ends, as a fraction of a loop counter-clockwise
  // from (radius_x, 0) looking along +x: 0 = robot 1's start, 0.5 = the far side of the
  // room, looking along -x. The walk itself (direction, speed, turn time) is unchanged.
  double start_phase = 0.0;
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
  // End of the slow turn back: the camera looks where it looked at turn_start() again.
  double look_away_end() const { return turn_end() + options_.hold_seconds + options_.return_seconds; }
  const TrajectoryOptions& options() const { return options_; }

 private:
  double loop_angle(double t) const;  // position angle on the ellipse, 0 .. 2*pi*loops
  double stopped_time(double t) const;  // integral of the walker's stop profile up to t
  double turn_yaw(double t) const;    // the look-away: 0, fast up to the turn angle, slowly back to 0
  double wobble(double t, int term) const;

  TrajectoryOptions options_;
  double duration_ = 0;
  double turn_centre_ = 0;
  double pause_half_width_ = 0;  // ramp time of the walker stopping and restarting
  double phases_[16] = {};
};

}  // namespace edge_slam
