#include "edge_slam/sim/trajectory.h"

#include "edge_slam/sim/random.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edge_slam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// 0 -> 1 with zero first and second derivatives at both ends.
double smootherstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * x * (x * (6 * x - 15) + 10);
}

// Hand-held wobble terms: (frequency Hz, amplitude). Units: metres for x/y/z, degrees for
// yaw/pitch/roll. Each frequency is rounded to a whole number of cycles over the sequence.
struct WobbleTerm { double hz, amplitude; };
constexpr WobbleTerm kWobble[] = {
    {0.07, 0.06}, {0.9, 0.012},    // x: slow drift, sway
    {0.05, 0.06}, {0.9, 0.012},    // y
    {0.1, 0.05}, {1.8, 0.012},     // z: slow height change, step bob
    {0.17, 3.0}, {0.37, 1.5},      // yaw
    {0.13, 4.0}, {0.43, 1.0},      // pitch
    {0.1, 2.0}, {0.57, 0.8},       // roll
};
constexpr double kPitchDegrees = -8.0;  // look slightly down: walls and floor, not the ceiling

}  // namespace

Trajectory::Trajectory(uint64_t seed, const TrajectoryOptions& options) : options_(options) {
  duration_ = options_.loop_seconds * options_.loops;
  turn_centre_ = 0.5 * duration_;
  pause_half_width_ = options_.turn_degrees > 0 ? 3.0 * options_.turn_seconds : 0.0;
  if (!std::isfinite(options_.start_phase))
    throw std::invalid_argument("the trajectory's start phase is not a finite number");
  if (options_.turn_degrees > 0 &&
      (turn_start() < pause_half_width_ || look_away_end() + pause_half_width_ > duration_))
    throw std::invalid_argument("the look-away turn does not fit in the trajectory's duration");
  SplitMix64 rng(seed ^ 0x7A5C3E1F00000000ull);
  for (double& p : phases_) p = rng.uniform(0, 2 * M_PI);
}

double Trajectory::wobble(double t, int term) const {
  const WobbleTerm& w = kWobble[term];
  const double cycles = std::max(1.0, std::round(w.hz * duration_));
  const double phase = 2 * M_PI * cycles * t / duration_ + phases_[term];
  return w.amplitude * std::sin(phase);
}

// Walking speed is 1 - stop(t): the walker ramps down (raised cosine over pause_half_width_),
// stands still from the fast turn until the slow turn back is over, and ramps up again, so the
// look-away starts and ends at the same place and heading. The angle is the closed-form
// integral of that speed, scaled to end at 2*pi*loops.
double Trajectory::stopped_time(double s) const {
  const double w = pause_half_width_;
  if (w <= 0) return 0.0;
  const double a = turn_start(), b = look_away_end();
  if (s <= a - w) return 0.0;
  if (s <= a) {  // ramping down: stop(x) = (1 - cos(pi x / w)) / 2
    const double x = s - (a - w);
    return 0.5 * (x - w / M_PI * std::sin(M_PI * x / w));
  }
  if (s <= b) return 0.5 * w + (s - a);
  if (s <= b + w) {  // ramping up: stop(x) = (1 + cos(pi x / w)) / 2
    const double x = s - b;
    return 0.5 * w + (b - a) + 0.5 * (x + w / M_PI * std::sin(M_PI * x / w));
  }
  return w + (b - a);
}

double Trajectory::loop_angle(double t) const {
  return 2 * M_PI * options_.loops * (t - stopped_time(t)) / (duration_ - stopped_time(duration_));
}

double Trajectory::turn_yaw(double t) const {
  if (options_.turn_degrees <= 0) return 0;
  const double away = smootherstep((t - turn_start()) / options_.turn_seconds);
  const double back = options_.return_seconds > 0
                          ? smootherstep((t - turn_end() - options_.hold_seconds) / options_.return_seconds)
                          : 0.0;
  return options_.turn_degrees * kDeg * (away - back);
}

Eigen::Isometry3d Trajectory::pose_at(double t) const {
  t = std::clamp(t, 0.0, duration_);
  // start_phase 0 adds exactly 0: robot 1's path is bit-for-bit what it was before the option.
  const double theta = 2 * M_PI * options_.start_phase + loop_angle(t);
  const Eigen::Vector3d position(options_.radius_x * std::cos(theta) + wobble(t, 0) + wobble(t, 1),
                                 options_.radius_y * std::sin(theta) + wobble(t, 2) + wobble(t, 3),
                                 options_.height + wobble(t, 4) + wobble(t, 5));
  // Heading: outward from the room centre, plus the look-away (which nets zero).
  const double yaw = theta + turn_yaw(t) + (wobble(t, 6) + wobble(t, 7)) * kDeg;
  const double pitch = (kPitchDegrees + wobble(t, 8) + wobble(t, 9)) * kDeg;
  const double roll = (wobble(t, 10) + wobble(t, 11)) * kDeg;

  // Optical axes when looking along world +x: x_c -> -y_w, y_c -> -z_w, z_c -> +x_w.
  Eigen::Matrix3d look_x;
  look_x << 0, 0, 1,
           -1, 0, 0,
            0, -1, 0;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix() * look_x;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = position;
  return T;
}

}  // namespace edge_slam
