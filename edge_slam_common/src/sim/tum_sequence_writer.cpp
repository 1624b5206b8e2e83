#include "edge_slam/sim/tum_sequence_writer.h"

#include "edge_slam/sim/renderer.h"
#include "edge_slam/sim/scene.h"
#include "edge_slam/sim/synthetic_camera.h"

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace edge_slam {
namespace fs = std::filesystem;

SequenceOptions SequenceOptions::long_variant(uint64_t seed) {
  SequenceOptions o;
  o.seed = seed;
  o.trajectory.loops = 24;
  o.fps = 15.0;
  o.jpeg = true;
  return o;
}

SequenceOptions SequenceOptions::second_robot(uint64_t seed) {
  SequenceOptions o;
  o.seed = seed;
  o.path_seed = seed + 1;
  o.trajectory.start_phase = 0.5;
  o.trajectory.turn_degrees = 0;
  o.trajectory.radius_x = 1.7;
  o.trajectory.radius_y = 1.0;
  o.trajectory.height = 1.3;
  return o;
}

int sequence_frame_count(const SequenceOptions& o) {
  const Trajectory trajectory(o.camera_seed(), o.trajectory);
  // The last frame lands exactly on the end of the loop, i.e. back at the start pose.
  const int all = static_cast<int>(std::floor(trajectory.duration() * o.fps + 1e-9)) + 1;
  return o.max_frames >= 0 ? std::min(all, o.max_frames) : all;
}

namespace {

std::string stamp_text(double stamp) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", stamp);
  return buf;
}

std::ofstream open_text(const fs::path& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  return f;
}

void close_text(std::ofstream& f, const fs::path& path) {
  f.close();
  if (!f) throw std::runtime_error("error writing " + path.string());
}

void write_image(const fs::path& path, const cv::Mat& img, const std::vector<int>& params) {
  if (!cv::imwrite(path.string(), img, params)) throw std::runtime_error("cannot write " + path.string());
}

std::string pose_text(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // one canonical sign per rotation
  char buf[192];
  const Eigen::Vector3d t = T.translation();
  std::snprintf(buf, sizeof buf, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f", t.x(), t.y(), t.z(), q.x(),
                q.y(), q.z(), q.w());
  return buf;
}

// The path's parameters for the list headers, only where they differ from the embedded default
// (whose files must stay byte-identical): "" for robot 1.
std::string path_note(const SequenceOptions& o) {
  const TrajectoryOptions d;
  const TrajectoryOptions& t = o.trajectory;
  if (!o.path_seed && t.start_phase == d.start_phase && t.radius_x == d.radius_x &&
      t.radius_y == d.radius_y && t.height == d.height && t.turn_degrees == d.turn_degrees &&
      t.loop_seconds == d.loop_seconds)
    return "";
  char buf[256];
  std::snprintf(buf, sizeof buf, " path seed %llu start phase %g ellipse %g x %g m height %g m loop %g s turn %g deg",
                static_cast<unsigned long long>(o.camera_seed()), t.start_phase, t.radius_x,
                t.radius_y, t.height, t.loop_seconds, t.turn_degrees);
  return buf;
}

void render_all(const fs::path& dir, const SequenceOptions& o, const ProgressFn& progress,
                SequenceReport& report) {
  using Clock = std::chrono::steady_clock;
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  const Scene scene = Scene::build(o.seed, o.texels_per_m);
  const Trajectory trajectory(o.camera_seed(), o.trajectory);
  const PinholeCamera camera = synthetic_room_camera(o.fps);
  RenderOptions render_options;
  render_options.supersample = o.supersample;

  const std::string origin = "edge_slam_synth seed " + std::to_string(o.seed) + path_note(o);
  auto header = [&](std::ofstream& f, const char* what, const char* columns) {
    f << "# " << what << "\n# file: '" << origin << "'\n# " << columns << "\n";
  };
  const fs::path rgb_txt = dir / "rgb.txt", depth_txt = dir / "depth.txt",
                 gt_txt = dir / "groundtruth.txt", assoc_txt = dir / "associations.txt";
  std::ofstream rgb_list = open_text(rgb_txt), depth_list = open_text(depth_txt),
                gt = open_text(gt_txt), assoc = open_text(assoc_txt);
  header(rgb_list, "color images", "timestamp filename");
  header(depth_list, "depth maps", "timestamp filename");
  header(gt, "ground truth trajectory", "timestamp tx ty tz qx qy qz qw");

  const std::string rgb_ext = o.jpeg ? ".jpg" : ".png";
  const std::vector<int> rgb_params =
      o.jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, 95} : std::vector<int>{};
  const int total = sequence_frame_count(o);
  for (int i = 0; i < total; ++i) {
    const double t = i / o.fps;
    const std::string stamp = stamp_text(o.first_stamp + t);
    const Eigen::Isometry3d T_wc = trajectory.pose_at(t);
    const auto start = Clock::now();
    RenderedFrame frame = render(scene, camera, T_wc, render_options);
    report.render_seconds += std::chrono::duration<double>(Clock::now() - start).count();
    if (o.sensor_noise) add_sensor_noise(frame.bgr, o.camera_seed(), static_cast<uint64_t>(i));

    const std::string rgb_name = "rgb/" + stamp + rgb_ext, depth_name = "depth/" + stamp + ".png";
    write_image(dir / rgb_name, frame.bgr, rgb_params);
    write_image(dir / depth_name, depth_to_tum16(frame.depth, camera.depth_factor), {});
    rgb_list << stamp << " " << rgb_name << "\n";
    depth_list << stamp << " " << depth_name << "\n";
    gt << stamp << " " << pose_text(T_wc) << "\n";
    assoc << stamp << " " << rgb_name << " " << stamp << " " << depth_name << "\n";
    report.frames = i + 1;
    if (progress) progress(i + 1, total);
  }
  close_text(rgb_list, rgb_txt);
  close_text(depth_list, depth_txt);
  close_text(gt, gt_txt);
  close_text(assoc, assoc_txt);

  const fs::path yaml_path = dir / "camera.yaml";
  std::ofstream yaml = open_text(yaml_path);
  yaml << camera_yaml(camera, "Synthetic room camera (rendered by edge_slam_synth): exact pinhole, no distortion.");
  close_text(yaml, yaml_path);
}

}  // namespace

SequenceReport write_tum_sequence(const std::string& out_dir, const SequenceOptions& o,
                                  const ProgressFn& progress) {
  if (out_dir.empty()) throw std::runtime_error("output folder name is empty");
  if (!(o.fps > 0)) throw std::runtime_error("fps must be positive");
  const auto start = std::chrono::steady_clock::now();
  fs::path out = fs::path(out_dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();  // "dir/" -> "dir"
  const fs::path tmp = out.string() + ".tmp";
  std::error_code ec;
  // Only ever replace an earlier output of this writer, never an arbitrary folder or file.
  if (fs::exists(out, ec) && !(fs::is_directory(out) && fs::exists(out / "rgb.txt") && fs::exists(out / "camera.yaml")))
    throw std::runtime_error("refusing to replace " + out.string() +
                             ": it exists and is not a sequence folder written by edge_slam_synth");
  SequenceReport report;
  fs::remove_all(tmp, ec);
  try {
    render_all(tmp, o, progress, report);
    fs::remove_all(out);
    fs::rename(tmp, out);
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(tmp, ec);
    throw std::runtime_error(std::string("cannot write ") + out.string() + ": " + e.what());
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  report.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace edge_slam
