// Monolithic runner (no ROS): runs Tracking + Local-Mapping + Loop-Closing (SlamSystem) on
// every associated frame of a TUM-format folder, waits for mapping and the full BA to
// finish, and writes <out>/trajectory.txt (TUM, T_wc of every tracked frame, relative to
// its reference keyframe's final pose), <out>/keyframes.txt, <out>/metrics.json and
// <out>/trajectory_online.txt (each frame's pose as tracked: what a robot would have navigated on),
// <out>/frame_times.csv (per frame: stamp, state, tracking wall/CPU ms; latency over time).
//
//   edge_slam_run --dataset <TUM folder> [--camera <yaml>] [--config config/slam.yaml]
//                 [--vocabulary <file>] --out <dir> [--max-frames N] [--mode monolithic]
//                 [--pace realtime|none|sync] [--rate R] [--no-mapping] [--no-loop] [--every K]
// --every K tracks only every K-th associated frame (frame-rate robustness tests).
// --pace sync is the deterministic replay for debugging: frames one by one, and after each
// one the runner waits until Local-Mapping and Loop-Closing have finished what it gave them,
// so a run does not depend on the machine's load (the figures come from --pace realtime).
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/io/metrics_json.h"
#include "edge_slam/io/trajectory_io.h"
#include "edge_slam/io/tum_dataset.h"
#include "edge_slam/io/vocabulary_io.h"
#include "edge_slam/module/local_mapping_params.h"
#include "edge_slam/module/module_metrics.h"
#include "edge_slam/module/slam_config.h"
#include "edge_slam/module/slam_system.h"
#include "edge_slam/module/tracking.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/timing_stats.h"

using namespace edge_slam;

namespace {

// One tracked frame's cost, as its TrackingResult reports it.
struct FrameTimes {
  double wall_ms = 0, cpu_ms = 0;
  TrackingStageTimes stages;
};

bool file_exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

int usage(const char* msg) {
  if (msg) std::cerr << "edge_slam_run: " << msg << "\n";
  std::cerr << "usage: edge_slam_run --dataset <TUM folder> [--camera <yaml>] [--config <slam.yaml>]\n"
               "                     [--vocabulary <file>] --out <dir> [--max-frames N] [--mode monolithic]\n"
               "                     [--pace realtime|none|sync] [--rate R] [--no-mapping] [--no-loop] [--every K]\n"
               "  --camera defaults to <dataset>/camera.yaml; --vocabulary to vocabulary/path in the config.\n"
               "  --pace realtime (default) feeds frames at their timestamps, as ORB-SLAM2's runner does;\n"
               "  --rate R (with --pace realtime) plays R times as fast as recorded (0.5: half speed, as rosbag\n"
               "  play -r 0.5 in the rostests, so their KeyFrame counts have a monolithic reference);\n"
               "  --pace none as fast as tracking goes; --pace sync (deterministic replay) also waits after\n"
               "  each frame until mapping and loop closing are idle, so a run is reproducible under any load;\n"
               "  there KeyFrame condition 2 sees the mapper busy for --sync-mapping-frames N (5) frames after\n"
               "  each KeyFrame, as a real-time mapper of ~170 ms per KeyFrame would be;\n"
               "  --no-mapping tracks only (no local mapping, no loop closing); --no-loop skips loop closing.\n";
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
  bool no_mapping = false, no_loop = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage(nullptr), 0;
    if (a == "--no-mapping" || a == "--no-loop") {
      (a == "--no-mapping" ? no_mapping : no_loop) = true;
      continue;
    }
    if (a.rfind("--", 0) != 0 || i + 1 >= argc) return usage(("bad argument '" + a + "'").c_str());
    args[a.substr(2)] = argv[++i];
  }
  for (const auto& [k, v] : args)
    if (k != "dataset" && k != "camera" && k != "config" && k != "vocabulary" && k != "out" && k != "max-frames" &&
        k != "mode" && k != "pace" && k != "rate" && k != "every" && k != "sync-mapping-frames")
      return usage(("unknown option --" + k).c_str());
  if (!args.count("dataset")) return usage("--dataset is required");
  if (!args.count("out")) return usage("--out is required");
  const std::string dataset_dir = args["dataset"];
  const std::string out_dir = args["out"];
  const std::string config_path = args.count("config") ? args["config"] : "config/slam.yaml";
  const std::string mode = args.count("mode") ? args["mode"] : "monolithic";
  if (mode != "monolithic") return usage(("--mode " + mode + ": only monolithic runs in this process").c_str());
  const std::string pace = args.count("pace") ? args["pace"] : "realtime";
  if (pace != "realtime" && pace != "none" && pace != "sync") return usage("--pace takes realtime, none or sync");
  double rate = 1.0;
  if (args.count("rate")) {
    char* end = nullptr;
    rate = std::strtod(args["rate"].c_str(), &end);
    if (end == args["rate"].c_str() || *end != '\0' || !(rate > 0.0) || !std::isfinite(rate))
      return usage(("--rate expects a number > 0, got '" + args["rate"] + "'").c_str());
    if (pace != "realtime") return usage("--rate only applies to --pace realtime");
  }

  try {
    if (!file_exists(dataset_dir)) throw std::runtime_error("dataset folder '" + dataset_dir + "' does not exist");
    std::string camera_path = args.count("camera") ? args["camera"] : dataset_dir + "/camera.yaml";
    if (!file_exists(camera_path))
      throw std::runtime_error("camera calibration '" + camera_path +
                               "' not found (give --camera <yaml>, e.g. config/camera_tum1.yaml)");
    const ConfigMap camera_cfg = ConfigMap::load(camera_path);
    const PinholeCamera camera = load_camera(camera_cfg);
    warn_unknown_keys(camera_cfg);
    const ConfigMap cfg = ConfigMap::load(config_path);
    check_slam_config(cfg);  // every section's values, and a warning for each key nothing reads
    const RunnerSettings runner = load_runner_settings(cfg);
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

    std::string vocab_path = args.count("vocabulary") ? args["vocabulary"] : runner.vocabulary_path;
    if (vocab_path.empty()) throw std::runtime_error("no vocabulary given (--vocabulary or vocabulary/path in " + config_path + ")");
    if (!file_exists(vocab_path)) throw std::runtime_error("vocabulary file '" + vocab_path + "' not found");
    std::cerr << "loading vocabulary " << vocab_path << " ...\n";
    auto vocabulary = std::make_shared<BowVocabulary>(load_vocabulary(vocab_path));
    if (vocabulary->empty()) throw std::runtime_error("vocabulary '" + vocab_path + "' is empty");

    const TumDataset dataset = TumDataset::open(dataset_dir);
    if (dataset.frames().empty()) throw std::runtime_error("dataset '" + dataset_dir + "' has no associated frames");
    if (::mkdir(out_dir.c_str(), 0755) != 0 && errno != EEXIST)
      throw std::runtime_error("cannot create output folder '" + out_dir + "'");

    SlamSystemOptions options;
    options.local_mapping = !no_mapping;
    options.loop_closing = !no_mapping && !no_loop;
    options.mapping = load_local_mapping_params(cfg);
    options.loop.verifier = load_loop_verifier_params(cfg);
    options.final_full_ba_iterations = runner.final_full_ba_iterations;
    // Deterministic replay: condition 2 sees a mapper that needs this many frames per KeyFrame.
    if (pace == "sync") options.simulated_mapping_frames = count_arg("sync-mapping-frames", 5, 1);
    // Images come from OpenCV's imread, which always yields BGR.
    SlamSystem slam(camera, orb, tracking_params, vocabulary, options, RgbEncoding::kBgr);
    const Map& map_ref = slam.map();
    const Map* map = &map_ref;

    const size_t n = max_frames >= 0 ? std::min<size_t>(max_frames, dataset.frames().size()) : dataset.frames().size();
    const auto wall_start = std::chrono::steady_clock::now();
    const double first_stamp = dataset.frames().empty() ? 0.0 : dataset.frames()[0].rgb_stamp;
    size_t processed = 0;
    std::vector<std::pair<double, Eigen::Isometry3d>> online;  // T_wc as tracked, before later corrections
    std::vector<FrameTimes> frame_times;  // every frame made (not the rejected inputs), for metrics.json
    std::ofstream frame_log(out_dir + "/frame_times.csv");
    frame_log << "stamp,state,pose_valid,keyframe,relocalized,keypoints,inliers,tracking_ms,tracking_cpu_ms,"
                 "path,initial_matches,initial_inliers,local_map_points,matches_before_final,reference_points,"
                 "tracked_close,untracked_close,keyframe_conditions,prediction_error_cm,prediction_error_deg,"
                 "mapping_queue,local_ba_aborted,weak_pose,last_frame_points";
    for (int s = 0; s < kTrackingStages; ++s) frame_log << ',' << to_string(static_cast<TrackingStage>(s)) << "_cpu_ms";
    frame_log << '\n' << std::fixed;
    for (size_t i = 0; i < n; i += static_cast<size_t>(every)) {
      ++processed;
      if (pace == "realtime") {  // do not run ahead of the camera
        const auto due =
            wall_start + std::chrono::duration<double>((dataset.frames()[i].rgb_stamp - first_stamp) / rate);
        std::this_thread::sleep_until(due);
      }
      cv::Mat rgb, depth;
      try {
        rgb = dataset.load_rgb(i);
        depth = dataset.load_depth(i);
      } catch (const std::exception& e) {
        std::cerr << "frame " << i << ": " << e.what() << "\n";
      }
      const TrackingResult r = slam.track_rgbd(rgb, depth, dataset.frames()[i].rgb_stamp);
      if (!r.input_rejected) frame_times.push_back(FrameTimes{r.time_ms, r.cpu_ms, r.stages});
      if (r.pose_valid) online.emplace_back(dataset.frames()[i].rgb_stamp, r.T_cw.inverse());
      if (pace == "sync" && !slam.wait_until_idle(600.0))
        std::cerr << "frame " << i << ": mapping did not become idle within 600 s\n";
      if (!r.message.empty() && (i < 3 || r.state != TrackingState::kOk))
        std::cerr << "frame " << i << " [" << to_string(r.state) << "]: " << r.message << "\n";
      if (r.relocalized) std::cerr << "frame " << i << ": relocalized\n";
      frame_log << std::setprecision(6) << dataset.frames()[i].rgb_stamp << ',' << to_string(r.state) << ','
                << r.pose_valid << ',' << r.new_keyframe << ',' << r.relocalized << ',' << r.keypoints << ',' << r.inliers
                << ',' << std::setprecision(3) << r.time_ms << ',' << r.cpu_ms << ',' << r.diag.path << ','
                << r.diag.initial_matches << ',' << r.diag.initial_inliers << ',' << r.diag.local_map_points << ','
                << r.diag.matches_before_final << ',' << r.diag.reference_points << ',' << r.diag.tracked_close << ','
                << r.diag.untracked_close << ',' << r.diag.keyframe_conditions << ',' << r.diag.prediction_error_m * 100
                << ',' << r.diag.prediction_error_deg << ',' << (slam.local_mapping() ? slam.local_mapping()->queued() : 0)
                << ',' << (slam.local_mapping() ? slam.local_mapping()->stats().local_ba_aborted : 0) << ','
                << r.diag.weak_pose << ',' << r.diag.last_frame_points;
      for (double ms : r.stages.cpu_ms) frame_log << ',' << ms;
      frame_log << '\n';
      if (processed % 100 == 0)
        std::cerr << "frame " << i + 1 << "/" << n << "  keyframes " << map->num_keyframes() << "  points "
                  << map->num_map_points() << "  inliers " << r.inliers << "  " << std::fixed
                  << std::setprecision(1) << r.time_ms << " ms\n";
    }
    if (!slam.finish(120.0)) std::cerr << "edge_slam_run: mapping/loop closing did not finish within 120 s\n";
    const auto trajectory = slam.trajectory();
    Tracking& tracking = slam.tracking();
    write_tum_trajectory(out_dir + "/trajectory.txt", trajectory);
    write_tum_trajectory(out_dir + "/trajectory_online.txt", online);
    write_keyframes(out_dir + "/keyframes.txt", *map);
    const TrackingCounters& c = tracking.counters();
    std::vector<double> wall_ms, cpu_ms;
    for (const FrameTimes& f : frame_times) {
      wall_ms.push_back(f.wall_ms);
      cpu_ms.push_back(f.cpu_ms);
    }
    const TimingStats t = summarize_times(wall_ms);
    const TimingStats cpu = summarize_times(cpu_ms);
    MetricsJson m;
    m.text("mode", no_mapping ? "tracking-only" : "monolithic")
        .text("dataset", dataset_dir)
        .integer("frames", static_cast<long long>(processed))
        .integer("every", every)
        .number("rate", rate)
        .integer("frames_tracked", c.frames_tracked)
        .integer("times_lost", c.times_lost)
        .integer("relocalizations", c.relocalizations)
        .integer("rejected_inputs", c.rejected_inputs)
        .integer("weak_frames", c.weak_frames)
        .integer("wide_motion_searches", c.wide_motion_searches)
        .integer("keyframes", static_cast<long long>(map->num_keyframes()))  // kept in the final map
        // Made by tracking, before Local-Mapping culled any: what the split's mobile count compares with.
        .integer("keyframes_created", c.keyframes_created)
        .integer("map_points", static_cast<long long>(map->num_map_points()));
    add_module_figures(m, collect_module_figures(slam.local_mapping(), slam.loop_closing()));
    m.timing_summary("tracking_cpu_ms", cpu).timing_summary("tracking_ms", t);
    // Per stage (util/stage_clock.h), CPU and wall: {"extract": {count, mean, median, p95, max}, ...}.
    MetricsJson stage_cpu, stage_wall;
    for (int s = 0; s < kTrackingStages; ++s) {
      std::vector<double> stage_cpu_ms, stage_wall_ms;
      for (const FrameTimes& f : frame_times) {
        stage_cpu_ms.push_back(f.stages.cpu_ms[s]);
        stage_wall_ms.push_back(f.stages.wall_ms[s]);
      }
      stage_cpu.timing(to_string(static_cast<TrackingStage>(s)), stage_cpu_ms);
      stage_wall.timing(to_string(static_cast<TrackingStage>(s)), stage_wall_ms);
    }
    m.object("tracking_stage_cpu_ms", stage_cpu).object("tracking_stage_ms", stage_wall);
    m.write(out_dir + "/metrics.json");
    std::cout << "frames " << processed << ", tracked " << c.frames_tracked << ", lost " << c.times_lost
              << " times, relocalized " << c.relocalizations << ", keyframes " << map->num_keyframes()
              << ", map points " << map->num_map_points() << ", loops closed "
              << (slam.loop_closing() ? slam.loop_closing()->loops_closed() : 0) << ", tracking ms median "
              << std::fixed << std::setprecision(1) << t.median << " p95 " << t.p95 << " max " << t.max
              << " (cpu median " << cpu.median << " p95 " << cpu.p95 << ")\n"
              << "wrote " << out_dir << "/{trajectory.txt,keyframes.txt,metrics.json}\n";
  } catch (const std::exception& e) {
    std::cerr << "edge_slam_run: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
