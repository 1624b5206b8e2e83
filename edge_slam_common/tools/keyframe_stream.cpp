// Edge throughput: records the KeyFrame records a mobile sends while tracking a TUM sequence,
// then replays them into an EdgeSession and measures how many KeyFrames per second its
// Local-Mapping gets through. No ROS: the records are the ones the nodelets put on the wire.
//
//   keyframe_stream record --dataset <TUM folder> --out <stream file> [--camera <yaml>]
//                          [--config config/slam.yaml] [--vocabulary <file>] [--max-frames N]
//   keyframe_stream replay --stream <file> [--camera <yaml>] [--config ...] [--vocabulary ...]
//                          [--mode sequential|flood] [--max-keyframes N] [--cores 1] [--json <file>]
//
// record: MobileSession on every frame as fast as it goes, without map updates from an edge
// (the mobile between two updates, on its own Local-Map), every record of its outbox kept in
// creation order; each KeyFrame counts as mapped by the edge 5 frames after it was sent, so
// the mobile's KeyFrame pacing (condition 2) sees the edge as a live one acknowledges. The file is in the Global-Map file format (io/map_file.h: versioned,
// checksummed), the records as its KeyFrames, in order. Never commit a stream recorded on a
// real dataset: it is derived from it.
// replay: a fresh EdgeSession takes the records in order, each marked as created well in the
// past so that condition 2 lets every one through to Local-Mapping (the backlog path):
//   sequential (default): the next record as soon as Local-Mapping has finished the previous
//     one, so each KeyFrame gets the whole treatment (triangulation, fusion, local BA,
//     KeyFrame culling): the rate the edge sustains at full quality;
//   flood: all records at once, as a burst after an outage; Local-Mapping then skips fusion
//     and local BA while KeyFrames wait, as designed.
// --cores N pins the process to the first N CPUs (default 1: "on one core"); the figure is
// KeyFrames / wall second from the first record to Local-Mapping and Loop-Closing idle, with
// the process CPU time next to it.
#include <sched.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <chrono>
#include <deque>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <string>
#include <thread>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/io/map_file.h"
#include "edge_slam/io/metrics_json.h"
#include "edge_slam/io/tum_dataset.h"
#include "edge_slam/io/vocabulary_io.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/timing_stats.h"
#include "edge_slam/util/wall_clock.h"

using namespace edge_slam;

namespace {

int usage(const char* msg) {
  if (msg) std::cerr << "keyframe_stream: " << msg << "\n";
  std::cerr << "usage: keyframe_stream record --dataset <TUM folder> --out <file> [--camera <yaml>] [--config <slam.yaml>]\n"
               "                              [--vocabulary <file>] [--max-frames N]\n"
               "       keyframe_stream replay --stream <file> [--camera <yaml>] [--config <slam.yaml>] [--vocabulary <file>]\n"
               "                              [--mode sequential|flood] [--max-keyframes N] [--cores N] [--json <file>]\n";
  return 1;
}

bool file_exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Setup {
  PinholeCamera camera;
  ConfigMap cfg;
  std::shared_ptr<const BowVocabulary> vocabulary;
};

Setup load_setup(std::map<std::string, std::string>& args, const std::string& default_camera) {
  Setup s;
  const std::string config = args.count("config") ? args["config"] : "config/slam.yaml";
  s.cfg = ConfigMap::load(config);
  const std::string camera = args.count("camera") ? args["camera"] : default_camera;
  if (camera.empty() || !file_exists(camera)) throw std::runtime_error("camera calibration '" + camera + "' not found (--camera)");
  s.camera = load_camera(camera);
  const std::string vocab = args.count("vocabulary") ? args["vocabulary"] : s.cfg.get_string("vocabulary/path", "");
  if (vocab.empty() || !file_exists(vocab)) throw std::runtime_error("vocabulary '" + vocab + "' not found (--vocabulary)");
  auto v = std::make_shared<BowVocabulary>(load_vocabulary(vocab));
  if (v->empty()) throw std::runtime_error("vocabulary '" + vocab + "' is empty");
  s.vocabulary = std::move(v);
  return s;
}

int record(std::map<std::string, std::string>& args) {
  if (!args.count("dataset") || !args.count("out")) return usage("record needs --dataset and --out");
  const std::string dataset_dir = args["dataset"];
  Setup s = load_setup(args, dataset_dir + "/camera.yaml");
  const TumDataset dataset = TumDataset::open(dataset_dir);
  size_t n = dataset.frames().size();
  if (args.count("max-frames")) n = std::min<size_t>(n, std::stoul(args["max-frames"]));
  // Images come from OpenCV's imread (BGR), as in the monolithic runner.
  MobileSession mobile(s.camera, load_orb_params(s.cfg), load_tracking_params(s.cfg), s.vocabulary,
                       load_mobile_session_params(s.cfg), RgbEncoding::kBgr);
  MapSnapshot stream;
  size_t tracked = 0;
  constexpr size_t kMappedAfterFrames = 5;       // as edge_slam_run --pace sync's default
  std::deque<std::pair<size_t, uint64_t>> sent;  // (frame index, seq) not yet acknowledged
  for (size_t i = 0; i < n; ++i) {
    const TrackingResult r = mobile.track(dataset.load_rgb(i), dataset.load_depth(i), dataset.frames()[i].rgb_stamp);
    tracked += r.pose_valid ? 1 : 0;
    while (auto rec = mobile.outbox().try_pop()) {
      sent.emplace_back(i, rec->seq);
      stream.content.keyframes.push_back(std::move(*rec));
    }
    // No edge here: a KeyFrame counts as mapped kMappedAfterFrames frames after it was sent, as
    // a live edge's Local-Mapping (~170 ms a KeyFrame on fr1) acknowledges it. Without this the
    // mobile's edge pacing (condition 2) sees a busy edge forever (one KeyFrame a second), and
    // with an always idle edge it makes one nearly every frame: neither is the stream a live
    // split sends.
    while (!sent.empty() && i >= sent.front().first + kMappedAfterFrames) {
      mobile.on_edge_progress(sent.front().second);
      sent.pop_front();
    }
  }
  if (stream.content.keyframes.empty()) throw std::runtime_error("no KeyFrame was made");
  stream.next_keyframe_id = stream.content.keyframes.back().id + 1;
  write_map_file(stream, args["out"]);
  std::cout << "recorded " << stream.content.keyframes.size() << " KeyFrames from " << n << " frames (" << tracked
            << " tracked) into " << args["out"] << "\n";
  return 0;
}

int replay(std::map<std::string, std::string>& args) {
  if (!args.count("stream")) return usage("replay needs --stream");
  const std::string mode = args.count("mode") ? args["mode"] : "sequential";
  if (mode != "sequential" && mode != "flood") return usage("--mode takes sequential or flood");
  const int cores = args.count("cores") ? std::stoi(args["cores"]) : 1;
  if (cores > 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    for (int c = 0; c < cores; ++c) CPU_SET(c, &set);
    if (sched_setaffinity(0, sizeof(set), &set) != 0) std::cerr << "keyframe_stream: cannot pin to " << cores << " core(s)\n";
  }
  Setup s = load_setup(args, "");
  MapSnapshot stream = read_map_file(args["stream"]);
  std::vector<KeyFrameRecord>& records = stream.content.keyframes;
  if (args.count("max-keyframes")) records.resize(std::min<size_t>(records.size(), std::stoul(args["max-keyframes"])));
  const OrbParams orb = load_orb_params(s.cfg);
  EdgeSessionParams params = load_edge_session_params(s.cfg);
  auto edge = std::make_unique<EdgeSession>(s.camera, orb.num_levels, orb.scale_factor, s.vocabulary, params);

  std::map<KeyFrameVerdict, int> verdicts;
  const double cpu0 = process_cpu_s();
  const auto t0 = std::chrono::steady_clock::now();
  for (KeyFrameRecord& r : records) {
    r.created_wall = wall_clock_seconds() - 10.0 * std::max(1.0, params.late_keyframe_age);  // backlog: past condition 2
    ++verdicts[edge->receive_keyframe(r, wall_clock_seconds())];
    if (mode == "sequential")
      while (!edge->mapping_idle()) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  if (!edge->wait_until_idle(600.0)) std::cerr << "keyframe_stream: the edge did not settle within 600 s\n";
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu_s = process_cpu_s() - cpu0;
  const ModuleFigures f = edge->module_figures();
  const int processed = f.mapping.keyframes_processed;
  const double rate = wall_s > 0 ? processed / wall_s : 0.0;
  const TimingStats lm = summarize_times(f.local_mapping_ms), ba = summarize_times(f.local_ba_ms);

  std::cout << std::fixed << std::setprecision(2) << "replayed " << records.size() << " KeyFrame records (" << mode
            << ", " << cores << " core(s)): " << verdicts[KeyFrameVerdict::kInserted] << " inserted, " << processed
            << " through Local-Mapping in " << wall_s << " s = " << rate << " KeyFrames/s; process CPU " << cpu_s
            << " s (" << (processed ? 1e3 * cpu_s / processed : 0.0) << " ms per KeyFrame)\n"
            << "  Local-Mapping per KeyFrame ms: median " << lm.median << " p95 " << lm.p95 << " | local BA ms: median "
            << ba.median << " p95 " << ba.p95 << " (" << f.mapping.local_ba_runs << " runs, " << f.mapping.local_ba_aborted
            << " aborted) | Global-Map " << edge->global_map()->num_keyframes() << " KeyFrames, "
            << edge->global_map()->num_map_points() << " points, loops " << f.loops_closed << "\n";
  if (args.count("json")) {
    MetricsJson m;
    m.text("mode", mode)
        .integer("cores", cores)
        .integer("records", static_cast<long long>(records.size()))
        .integer("inserted", verdicts[KeyFrameVerdict::kInserted])
        .integer("processed", processed)
        .number("wall_s", wall_s)
        .number("cpu_s", cpu_s)
        .number("keyframes_per_s", rate)
        .number("cpu_ms_per_keyframe", processed ? 1e3 * cpu_s / processed : 0.0)
        .integer("global_map_keyframes", static_cast<long long>(edge->global_map()->num_keyframes()))
        .integer("global_map_points", static_cast<long long>(edge->global_map()->num_map_points()));
    add_module_figures(m, f);
    m.write(args["json"]);
  }
  edge.reset();  // joins the mapping threads before the vocabulary goes
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage(nullptr);
  const std::string command = argv[1];
  if (command == "-h" || command == "--help") return usage(nullptr), 0;
  std::map<std::string, std::string> args;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0 || i + 1 >= argc) return usage(("bad argument '" + a + "'").c_str());
    args[a.substr(2)] = argv[++i];
  }
  try {
    if (command == "record") return record(args);
    if (command == "replay") return replay(args);
    return usage(("unknown command '" + command + "'").c_str());
  } catch (const std::exception& e) {
    std::cerr << "keyframe_stream: error: " << e.what() << "\n";
    return 1;
  }
}
