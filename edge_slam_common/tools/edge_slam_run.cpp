// Monolithic runner (no ROS): tracks every associated frame of a TUM-format folder and
// writes <out>/trajectory.txt (TUM, T_wc of every tracked frame), <out>/keyframes.txt and
// <out>/metrics.json.
//
//   edge_slam_run --dataset <TUM folder> [--camera <yaml>] [--config config/slam.yaml]
//                 [--vocabulary <file>] --out <dir> [--max-frames N] [--every K]
// --every K tracks only every K-th associated frame (frame-rate robustness tests).
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/io/trajectory_io.h"
#include "edge_slam/io/tum_dataset.h"
#include "edge_slam/io/vocabulary_io.h"
#include "edge_slam/module/tracking.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/timing_stats.h"

using namespace edge_slam;

namespace {

bool file_exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

int usage(const char* msg) {
  if (msg) std::cerr << "edge_slam_run: " << msg << "\n";
  std::cerr << "usage: edge_slam_run --dataset <TUM folder> [--camera <yaml>] [--config <slam.yaml>]\n"
               "                     [--vocabulary <file>] --out <dir> [--max-frames N] [--every K]\n"
               "  --camera defaults to <dataset>/camera.yaml; --vocabulary to vocabulary/path in the config.\n";
  return 1;
}

void write_keyframes(const std::string& path, const Map& map) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
  out << "# keyframe_id frame_id timestamp tx ty tz qx qy qz qw (T_wc)\n";
  for (const auto& kf : map.keyframes()) {
    out << kf->id() << ' ' << kf->frame_id() << ' ';
    write_tum_pose(out, kf->stamp(), kf->T_wc());
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage(nullptr), 0;
    if (a.rfind("--", 0) != 0 || i + 1 >= argc) return usage(("bad argument '" + a + "'").c_str());
    args[a.substr(2)] = argv[++i];
  }
  for (const auto& [k, v] : args)
    if (k != "dataset" && k != "camera" && k != "config" && k != "vocabulary" && k != "out" && k != "max-frames" &&
        k != "every")
      return usage(("unknown option --" + k).c_str());
  if (!args.count("dataset")) return usage("--dataset is required");
  if (!args.count("out")) return usage("--out is required");
  const std::string dataset_dir = args["dataset"];
  const std::string out_dir = args["out"];
  const std::string config_path = args.count("config") ? args["config"] : "config/slam.yaml";

  try {
    if (!file_exists(dataset_dir)) throw std::runtime_error("dataset folder '" + dataset_dir + "' does not exist");
    std::string camera_path = args.count("camera") ? args["camera"] : dataset_dir + "/camera.yaml";
    if (!file_exists(camera_path))
      throw std::runtime_error("camera calibration '" + camera_path +
                               "' not found (give --camera <yaml>, e.g. config/camera_tum1.yaml)");
    const PinholeCamera camera = load_camera(camera_path);
    const ConfigMap cfg = ConfigMap::load(config_path);
    const OrbParams orb = load_orb_params(cfg);
    const TrackingParams tracking_params = load_tracking_params(cfg);
    auto count_arg = [&](const std::string& key, int def, int min) {
      if (!args.count(key)) return def;
      size_t used = 0;
      int v = 0;
      try {
        v = std::stoi(args[key], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != args[key].size() || v < min)
        throw std::runtime_error("--" + key + " expects an integer >= " + std::to_string(min) + ", got '" +
                                 args[key] + "'");
      return v;
    };
    const int max_frames = count_arg("max-frames", -1, 0);
    const int every = count_arg("every", 1, 1);

    std::string vocab_path = args.count("vocabulary") ? args["vocabulary"] : cfg.get_string("vocabulary/path", "");
    if (vocab_path.empty()) throw std::runtime_error("no vocabulary given (--vocabulary or vocabulary/path in " + config_path + ")");
    if (!file_exists(vocab_path)) throw std::runtime_error("vocabulary file '" + vocab_path + "' not found");
    std::cerr << "loading vocabulary " << vocab_path << " ...\n";
    auto vocabulary = std::make_shared<BowVocabulary>(load_vocabulary(vocab_path));
    if (vocabulary->empty()) throw std::runtime_error("vocabulary '" + vocab_path + "' is empty");

    const TumDataset dataset = TumDataset::open(dataset_dir);
    if (dataset.frames().empty()) throw std::runtime_error("dataset '" + dataset_dir + "' has no associated frames");
    if (::mkdir(out_dir.c_str(), 0755) != 0 && errno != EEXIST)
      throw std::runtime_error("cannot create output folder '" + out_dir + "'");

    auto map = std::make_shared<Map>();
    auto database = std::make_shared<KeyFrameDatabase>();
    // Images come from OpenCV's imread, which always yields BGR.
    Tracking tracking(camera, orb, tracking_params, map, database, vocabulary, RgbEncoding::kBgr);
    // No local mapping yet: the mapper is reported idle, keyframes stay in the map as inserted.
    tracking.set_mapper_idle(true);

    std::vector<std::pair<double, Eigen::Isometry3d>> trajectory;
    const size_t n = max_frames >= 0 ? std::min<size_t>(max_frames, dataset.frames().size()) : dataset.frames().size();
    size_t processed = 0;
    for (size_t i = 0; i < n; i += static_cast<size_t>(every)) {
      ++processed;
      cv::Mat rgb, depth;
      try {
        rgb = dataset.load_rgb(i);
        depth = dataset.load_depth(i);
      } catch (const std::exception& e) {
        std::cerr << "frame " << i << ": " << e.what() << "\n";
      }
      const TrackingResult r = tracking.track_rgbd(rgb, depth, dataset.frames()[i].rgb_stamp);
      if (r.pose_valid) trajectory.emplace_back(dataset.frames()[i].rgb_stamp, r.T_cw.inverse());
      if (!r.message.empty() && (i < 3 || r.state != TrackingState::kOk))
        std::cerr << "frame " << i << " [" << to_string(r.state) << "]: " << r.message << "\n";
      if (r.relocalized) std::cerr << "frame " << i << ": relocalized\n";
      if (processed % 100 == 0)
        std::cerr << "frame " << i + 1 << "/" << n << "  keyframes " << map->num_keyframes() << "  points "
                  << map->num_map_points() << "  inliers " << r.inliers << "  " << std::fixed
                  << std::setprecision(1) << r.time_ms << " ms\n";
    }

    write_tum_trajectory(out_dir + "/trajectory.txt", trajectory);
    write_keyframes(out_dir + "/keyframes.txt", *map);
    const TrackingCounters& c = tracking.counters();
    const TimingStats t = summarize_times(tracking.frame_times_ms());
    const TimingStats cpu = summarize_times(tracking.frame_cpu_times_ms());
    std::ofstream m(out_dir + "/metrics.json");
    m << std::fixed << std::setprecision(3) << "{\n"
      << "  \"mode\": \"monolithic\",\n"
      << "  \"dataset\": \"" << dataset_dir << "\",\n"
      << "  \"frames\": " << processed << ",\n"
      << "  \"every\": " << every << ",\n"
      << "  \"frames_tracked\": " << c.frames_tracked << ",\n"
      << "  \"times_lost\": " << c.times_lost << ",\n"
      << "  \"relocalizations\": " << c.relocalizations << ",\n"
      << "  \"rejected_inputs\": " << c.rejected_inputs << ",\n"
      << "  \"keyframes\": " << map->num_keyframes() << ",\n"
      << "  \"map_points\": " << map->num_map_points() << ",\n"
      << "  \"tracking_ms\": {\"mean\": " << t.mean << ", \"median\": " << t.median << ", \"p95\": " << t.p95
      << ", \"max\": " << t.max << "},\n"
      << "  \"tracking_cpu_ms\": {\"mean\": " << cpu.mean << ", \"median\": " << cpu.median << ", \"p95\": " << cpu.p95
      << ", \"max\": " << cpu.max << "}\n"
      << "}\n";
    if (!m) throw std::runtime_error("cannot write '" + out_dir + "/metrics.json'");
    std::cout << "frames " << processed << ", tracked " << c.frames_tracked << ", lost " << c.times_lost
              << " times, relocalized " << c.relocalizations << ", keyframes " << map->num_keyframes()
              << ", map points " << map->num_map_points() << ", tracking ms median " << std::fixed << std::setprecision(1)
              << t.median << " p95 " << t.p95 << " max " << t.max << " (cpu median " << cpu.median << " p95 " << cpu.p95
              << ")\n"
              << "wrote " << out_dir << "/{trajectory.txt,keyframes.txt,metrics.json}\n";
  } catch (const std::exception& e) {
    std::cerr << "edge_slam_run: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
