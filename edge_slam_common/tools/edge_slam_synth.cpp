// edge_slam_synth: renders the embedded synthetic RGB-D room sequence as a TUM-format folder,
// or (--robot2 and the path options) a second robot's walk through the same room.
#include "edge_slam/sim/tum_sequence_writer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <string>

namespace {

const char* kUsage = R"(Usage: edge_slam_synth --out DIR [--seed N] [--long] [--frames N] [--fps F] [--jpg|--png]
                      [--robot2] [--start-phase F] [--radius-x M] [--radius-y M] [--height M]
                      [--loop-seconds S] [--no-turn] [--path-seed N]

Renders a textured 8 x 6 x 3 m room with furniture, seen by a hand-held RGB-D camera
(640x480, fx=fy=525, cx=319.5, cy=239.5, no distortion) walking one loop around the room
(30 s, back to its start pose, one fast ~90 degree turn in 0.4 s mid-way), into a folder laid
out like a TUM RGB-D benchmark sequence:
  rgb/<stamp>.png|jpg  depth/<stamp>.png (16-bit, metres * 5000, 0 = no reading)
  rgb.txt depth.txt groundtruth.txt (camera optical frame in world, z up) associations.txt
  camera.yaml
Frames are stamped 1000000000.0 + i / fps. Output goes to DIR.tmp, renamed to DIR when done.
The same seed always gives byte-identical files.

Options:
  --out DIR     output folder (replaced if it exists)
  --seed N      scene textures, furniture layout, and (unless --path-seed or --robot2)
                hand-held wobble and sensor noise (default 42)
  --long        24 loops (12 minutes, 10801 frames); defaults to 15 fps and JPEG colour
                (about 3 GB and ~30 CPU-minutes, instead of ~16 GB for 30 fps PNG)
  --frames N    stop after the first N frames
  --fps F       frame rate (default 30, or 15 with --long); the path's timing is unchanged
  --jpg / --png colour image format (default PNG, or JPEG quality 95 with --long)
  --help        this text

A second robot in the same room (issue #16): the same --seed gives the identical room, and
every path is written in the same world frame with the same stamps (frame 0 at
1000000000.0), so two sequences play together as two robots starting at once.
  --robot2          preset for robot 2: --start-phase 0.5 --radius-x 1.7 --radius-y 1.0
                    --height 1.3 --no-turn --path-seed SEED+1 (one 30 s loop starting on the
                    far side of the room, looking at what robot 1 faces ~12 s in; robot 2
                    reaches robot 1's start view half-way). The options below override it.
                    With --long: 24 such loops.
  --start-phase F   where on the loop the path starts, as a fraction of a loop in [0, 1)
                    counter-clockwise from (radius-x, 0) looking along +x (default 0)
  --radius-x M      loop ellipse half-axis along x in (0, 3] m (default 2.0)
  --radius-y M      loop ellipse half-axis along y in (0, 2] m (default 1.2)
  --height M        mean camera height in [0.3, 2.5] m (default 1.4)
  --loop-seconds S  duration of one loop in [5, 600] s (default 30): the sequence lasts
                    one loop (24 with --long)
  --no-turn         no fast look-away turn (default: one, mid-sequence)
  --path-seed N     seed of the camera's wobble and sensor noise only (default: --seed); the
                    room stays the one of --seed
Robot 1 (no path option) is the embedded default, byte-identical to earlier versions.
)";

bool parse_number(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0';
}

int fail(const std::string& message) {
  std::fprintf(stderr, "edge_slam_synth: %s\n(see edge_slam_synth --help)\n", message.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  double seed = 42, frames = -1, fps = -1;
  bool long_variant = false, robot2 = false, no_turn = false;
  // Path overrides, NaN = not given.
  const double unset = std::numeric_limits<double>::quiet_NaN();
  double start_phase = unset, radius_x = unset, radius_y = unset, height = unset,
         loop_seconds = unset, path_seed = unset;
  auto is_integer = [](double v) { return v >= 0 && v <= 9e15 && v == static_cast<double>(static_cast<long long>(v)); };
  int image_format = 0;  // 0 default, 1 jpg, 2 png
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](double& target) {
      if (i + 1 >= argc || !parse_number(argv[i + 1], target)) return false;
      ++i;
      return true;
    };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (arg == "--seed") {
      if (!value(seed) || !is_integer(seed)) return fail("--seed needs a non-negative integer");
    } else if (arg == "--path-seed") {
      if (!value(path_seed) || !is_integer(path_seed)) return fail("--path-seed needs a non-negative integer");
    } else if (arg == "--robot2") {
      robot2 = true;
    } else if (arg == "--no-turn") {
      no_turn = true;
    } else if (arg == "--start-phase") {
      if (!value(start_phase) || !(start_phase >= 0 && start_phase < 1))
        return fail("--start-phase needs a number in [0, 1)");
    } else if (arg == "--radius-x") {
      if (!value(radius_x) || !(radius_x > 0 && radius_x <= 3)) return fail("--radius-x needs a number in (0, 3]");
    } else if (arg == "--radius-y") {
      if (!value(radius_y) || !(radius_y > 0 && radius_y <= 2)) return fail("--radius-y needs a number in (0, 2]");
    } else if (arg == "--height") {
      if (!value(height) || !(height >= 0.3 && height <= 2.5)) return fail("--height needs a number in [0.3, 2.5]");
    } else if (arg == "--loop-seconds") {
      if (!value(loop_seconds) || !(loop_seconds >= 5 && loop_seconds <= 600))
        return fail("--loop-seconds needs a number in [5, 600]");
    } else if (arg == "--frames") {
      if (!value(frames) || frames < 1 || frames > 1e7) return fail("--frames needs a positive integer");
    } else if (arg == "--fps") {
      if (!value(fps) || !(fps > 0 && fps <= 120)) return fail("--fps needs a number in (0, 120]");
    } else if (arg == "--long") {
      long_variant = true;
    } else if (arg == "--jpg") {
      image_format = 1;
    } else if (arg == "--png") {
      image_format = 2;
    } else {
      return fail("unknown or incomplete argument '" + arg + "'");
    }
  }
  if (out.empty()) return fail("--out DIR is required");

  const uint64_t s = static_cast<uint64_t>(seed);
  edge_slam::SequenceOptions options = long_variant ? edge_slam::SequenceOptions::long_variant(s)
                                                    : edge_slam::SequenceOptions();
  options.seed = s;
  if (fps > 0) options.fps = fps;
  if (frames > 0) options.max_frames = static_cast<int>(frames);
  if (image_format) options.jpeg = image_format == 1;
  if (robot2) {  // the second robot's path, keeping --long's loops and the image settings
    edge_slam::SequenceOptions second = edge_slam::SequenceOptions::second_robot(s);
    options.path_seed = second.path_seed;
    second.trajectory.loops = options.trajectory.loops;
    options.trajectory = second.trajectory;
  }
  if (!std::isnan(path_seed)) options.path_seed = static_cast<uint64_t>(path_seed);
  if (!std::isnan(start_phase)) options.trajectory.start_phase = start_phase;
  if (!std::isnan(radius_x)) options.trajectory.radius_x = radius_x;
  if (!std::isnan(radius_y)) options.trajectory.radius_y = radius_y;
  if (!std::isnan(height)) options.trajectory.height = height;
  if (!std::isnan(loop_seconds)) options.trajectory.loop_seconds = loop_seconds;
  if (no_turn) options.trajectory.turn_degrees = 0;

  int total = 0;
  try {
    total = edge_slam::sequence_frame_count(options);  // also checks that the path is valid
  } catch (const std::exception& e) {
    return fail(e.what());
  }
  const edge_slam::TrajectoryOptions& path = options.trajectory;
  if (robot2 || options.path_seed || path.start_phase != 0 || path.turn_degrees == 0)
    std::fprintf(stderr, "edge_slam_synth: path seed %llu, start phase %g, ellipse %g x %g m at %g m, %g s/loop, %s\n",
                 static_cast<unsigned long long>(options.camera_seed()), path.start_phase, path.radius_x,
                 path.radius_y, path.height, path.loop_seconds,
                 path.turn_degrees > 0 ? "with the look-away turn" : "no turn");
  std::fprintf(stderr, "edge_slam_synth: seed %llu, %d frames at %g fps, %s colour -> %s\n",
               static_cast<unsigned long long>(s), total, options.fps, options.jpeg ? "JPEG" : "PNG",
               out.c_str());
  const auto start = std::chrono::steady_clock::now();
  auto progress = [&](int done, int all) {
    if (done % 50 != 0 && done != all) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "  frame %d/%d  %.1f s elapsed, %.3f s/frame\n", done, all, elapsed, elapsed / done);
  };
  try {
    const edge_slam::SequenceReport r = edge_slam::write_tum_sequence(out, options, progress);
    std::fprintf(stderr, "edge_slam_synth: wrote %d frames to %s in %.1f s (render %.3f s/frame)\n",
                 r.frames, out.c_str(), r.total_seconds, r.render_seconds / std::max(1, r.frames));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edge_slam_synth: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
