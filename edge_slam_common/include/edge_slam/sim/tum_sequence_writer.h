// Renders the synthetic room along its trajectory into a folder laid out exactly like a TUM
// RGB-D benchmark sequence: rgb/, depth/, rgb.txt, depth.txt, groundtruth.txt,
// associations.txt, plus camera.yaml. Output goes to <out>.tmp, renamed to <out> when complete.
#pragma once
#include "edge_slam/sim/trajectory.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace edge_slam {

struct SequenceOptions {
  uint64_t seed = 42;                // the room: textures and furniture (and, by default, the camera)
  // The camera's own randomness: hand-held wobble phases and sensor noise. Unset: seed, which
  // is what robot 1 (the embedded default) uses. A second robot in the same room keeps seed
  // (the identical world) and sets this so that its wobble and noise are its own.
  std::optional<uint64_t> path_seed;
  TrajectoryOptions trajectory;      // loops, duration, fast turn
  double fps = 30.0;
  int max_frames = -1;               // < 0: the whole trajectory (duration * fps + 1 frames)
  bool jpeg = false;                 // colour as JPEG (quality 95) instead of PNG
  bool sensor_noise = true;
  double first_stamp = 1000000000.0; // seconds; frame i is stamped first_stamp + i / fps
  int supersample = 2;
  double texels_per_m = 256;         // texture resolution (tests use less to run fast)

  uint64_t camera_seed() const { return path_seed.value_or(seed); }

  // The --long variant: 24 loops (12 minutes) at 15 fps with JPEG colour.
  static SequenceOptions long_variant(uint64_t seed);
  // The --robot2 preset (issue #16): a second robot in the same room (scene seed `seed`, same
  // world frame, same stamps: both start at first_stamp), one 30 s loop like robot 1's but
  // starting half a loop ahead (on the far side, looking at what robot 1 faces ~12 s in), on a
  // slightly smaller ellipse (1.7 x 1.0 m) 10 cm lower, without the look-away turn, wobble and
  // noise from path seed `seed + 1`. Its views overlap robot 1's on every wall, at other times.
  static SequenceOptions second_robot(uint64_t seed);
};

struct SequenceReport {
  int frames = 0;
  double render_seconds = 0;  // ray casting only
  double total_seconds = 0;   // including scene building and encoding
};

// Called after each frame with (frames done, frames total).
using ProgressFn = std::function<void(int, int)>;

// Throws std::runtime_error (naming the path) if anything cannot be written; the partial
// <out>.tmp is removed then. An existing <out> is replaced only after success, and only if it
// looks like an earlier output (a folder with rgb.txt and camera.yaml); otherwise it throws.
SequenceReport write_tum_sequence(const std::string& out_dir, const SequenceOptions& options,
                                  const ProgressFn& progress = nullptr);

// Number of frames the options produce.
int sequence_frame_count(const SequenceOptions& options);

}  // namespace edge_slam
