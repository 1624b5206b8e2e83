// Wire micro-benchmark (benchmark suite, issue "Benchmark suite"): what one KeyFrame and one
// Local-Map update cost on the wire, measured on real records instead of estimated.
// Runs the mobile (MobileSession) and the edge (EdgeSession) in this process on a TUM folder,
// with no ROS master: every KeyFrame record the mobile emits goes through the bridge
// (to_message), ros::serialization into a byte buffer, back out (deserialize, from_message) and
// into the edge. Every `--update-every` frames the edge builds a Local-Map update, which takes
// the same round trip and is then rebuilt into an empty map exactly as the mobile rebuilds its
// Local-Map (rebuild_from_update), so the rebuild latency does not depend on the acceptance rule;
// the mobile session is offered the same update through its acceptance policy.
//
//   wire_benchmark --dataset <TUM folder> [--camera <yaml>] [--config config/slam.yaml]
//                  [--vocabulary <file>] [--frames N] [--update-every K] --out <file.json>
#include <ros/serialization.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/map.h"
#include "edge_slam/data/scale_pyramid.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/io/tum_dataset.h"
#include "edge_slam/io/vocabulary_io.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/slam_config.h"
#include "edge_slam/util/wall_clock.h"
#include "edge_slam/module/tracking_params.h"
#include "edge_slam/util/timing_stats.h"
#include "edge_slam_bridge/message_conversion.h"

using namespace edge_slam;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// One message's round trip through the bridge and ROS serialization, timed in two halves.
struct RoundTrip {
  size_t bytes = 0;
  double serialize_ms = 0;    // record -> message (quantise) -> bytes
  double deserialize_ms = 0;  // bytes -> message -> record (validate)
};

template <typename Record>
RoundTrip round_trip(const Record& in, Record& out) {
  using Msg = decltype(to_message(in));
  RoundTrip r;
  auto t0 = Clock::now();
  const Msg msg = to_message(in);
  r.bytes = ros::serialization::serializationLength(msg);
  std::vector<uint8_t> buffer(r.bytes);
  ros::serialization::OStream os(buffer.data(), static_cast<uint32_t>(buffer.size()));
  ros::serialization::serialize(os, msg);
  r.serialize_ms = ms_since(t0);

  t0 = Clock::now();
  Msg decoded;
  ros::serialization::IStream is(buffer.data(), static_cast<uint32_t>(buffer.size()));
  ros::serialization::deserialize(is, decoded);
  const DecodeStatus status = from_message(decoded, out);
  r.deserialize_ms = ms_since(t0);
  if (!status.ok) throw std::runtime_error("round trip rejected: " + status.error);
  return r;
}

void write_stats(std::ostream& out, const char* name, const std::vector<double>& v, bool last = false) {
  const TimingStats s = summarize_times(v);
  out << "  \"" << name << "\": {\"count\": " << s.count << ", \"mean\": " << s.mean << ", \"median\": " << s.median
      << ", \"p95\": " << s.p95 << ", \"max\": " << s.max << "}" << (last ? "\n" : ",\n");
}

int usage(const std::string& msg) {
  if (!msg.empty()) std::cerr << "wire_benchmark: " << msg << "\n";
  std::cerr << "usage: wire_benchmark --dataset <TUM folder> [--camera <yaml>] [--config config/slam.yaml]\n"
               "                      [--vocabulary <file>] [--frames N] [--update-every K] --out <file.json>\n";
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage(""), 0;
    if (a.rfind("--", 0) != 0 || i + 1 >= argc) return usage("bad argument '" + a + "'");
    args[a.substr(2)] = argv[++i];
  }
  for (const auto& [k, v] : args)
    if (k != "dataset" && k != "camera" && k != "config" && k != "vocabulary" && k != "frames" &&
        k != "update-every" && k != "out")
      return usage("unknown option --" + k);
  if (!args.count("dataset") || !args.count("out")) return usage("--dataset and --out are required");
  try {
    const std::string dataset_dir = args["dataset"];
    const ConfigMap cfg = ConfigMap::load(args.count("config") ? args["config"] : "config/slam.yaml");
    const PinholeCamera camera = load_camera(args.count("camera") ? args["camera"] : dataset_dir + "/camera.yaml");
    const OrbParams orb = load_orb_params(cfg);
    TrackingParams tracking = load_tracking_params(cfg);
    tracking.conditions = KeyFrameConditionSet::kMobile;  // as the mobile nodelet: 1-2 run on the edge
    const std::string vocab_path =
        args.count("vocabulary") ? args["vocabulary"] : load_runner_settings(cfg).vocabulary_path;
    auto vocabulary = std::make_shared<BowVocabulary>(load_vocabulary(vocab_path));
    const TumDataset dataset = TumDataset::open(dataset_dir);
    const size_t frames = std::min<size_t>(args.count("frames") ? std::stoul(args["frames"]) : 300,
                                           dataset.frames().size());
    const size_t update_every = args.count("update-every") ? std::stoul(args["update-every"]) : 30;
    if (update_every == 0) return usage("--update-every must be >= 1");

    MobileSession mobile(camera, orb, tracking, vocabulary, load_mobile_session_params(cfg), RgbEncoding::kBgr);
    EdgeSession edge(camera, orb.num_levels, orb.scale_factor, vocabulary, load_edge_session_params(cfg));
    const auto pyramid = std::make_shared<ScalePyramid>(ScalePyramid::make(orb.num_levels, orb.scale_factor));

    std::vector<double> kf_bytes, kf_keypoints, kf_new_points, kf_ser, kf_deser, kf_total;
    size_t updates_applied = 0;
    std::vector<double> up_bytes, up_keyframes, up_points, up_ser, up_deser, stage, rebuild;
    for (size_t i = 0; i < frames; ++i) {
      const double stamp = dataset.frames()[i].rgb_stamp;
      mobile.track(dataset.load_rgb(i), dataset.load_depth(i), stamp);
      while (auto record = mobile.outbox().try_pop()) {
        KeyFrameRecord received;
        const RoundTrip r = round_trip(*record, received);
        kf_bytes.push_back(static_cast<double>(r.bytes));
        kf_keypoints.push_back(static_cast<double>(record->features.size()));
        kf_new_points.push_back(static_cast<double>(record->new_points.size()));
        kf_ser.push_back(r.serialize_ms);
        kf_deser.push_back(r.deserialize_ms);
        kf_total.push_back(r.serialize_ms + r.deserialize_ms);
        edge.receive_keyframe(received, wall_clock_seconds());
      }
      if (i % update_every != update_every - 1) continue;
      edge.wait_until_idle(30.0);
      const std::optional<MapUpdateRecord> update = edge.build_local_map_update(stamp);
      if (!update) continue;
      MapUpdateRecord received;
      const RoundTrip r = round_trip(*update, received);
      Map local_map;
      const auto t0 = Clock::now();
      StagedUpdate staged = stage_update(received, camera, pyramid, vocabulary.get());
      stage.push_back(ms_since(t0));
      const auto t1 = Clock::now();
      install_update(local_map, staged);  // what tracking waits for
      rebuild.push_back(ms_since(t1));
      up_bytes.push_back(static_cast<double>(r.bytes));
      up_keyframes.push_back(static_cast<double>(received.keyframes.size()));
      up_points.push_back(static_cast<double>(received.points.size()));
      up_ser.push_back(r.serialize_ms);
      up_deser.push_back(r.deserialize_ms);
      // The mobile gets it too (through its acceptance policy), so its Local-Map and hence its
      // KeyFrame rate behave as in the split instead of drifting without the edge's map points.
      if (mobile.apply_update(received, stamp).decision == UpdateDecision::kAccept) ++updates_applied;
      std::cerr << "\rwire_benchmark: frame " << i + 1 << "/" << frames << ", " << kf_bytes.size()
                << " KeyFrames, " << up_bytes.size() << " updates" << std::flush;
    }
    std::cerr << "\n";

    std::ofstream out(args["out"]);
    out << std::fixed << std::setprecision(4) << "{\n"
        << "  \"dataset\": \"" << dataset_dir << "\",\n"
        << "  \"frames\": " << frames << ",\n"
        << "  \"orb_features\": " << orb.num_features << ",\n"
        << "  \"update_every_frames\": " << update_every << ",\n"
        << "  \"updates_applied_by_mobile\": " << updates_applied << ",\n";
    write_stats(out, "keyframe_bytes", kf_bytes);
    write_stats(out, "keyframe_keypoints", kf_keypoints);
    write_stats(out, "keyframe_new_points", kf_new_points);
    write_stats(out, "keyframe_serialize_ms", kf_ser);
    write_stats(out, "keyframe_deserialize_ms", kf_deser);
    write_stats(out, "keyframe_roundtrip_ms", kf_total);
    write_stats(out, "update_bytes", up_bytes);
    write_stats(out, "update_keyframes", up_keyframes);
    write_stats(out, "update_points", up_points);
    write_stats(out, "update_serialize_ms", up_ser);
    write_stats(out, "update_deserialize_ms", up_deser);
    write_stats(out, "update_stage_ms", stage);
    write_stats(out, "update_rebuild_ms", rebuild, true);
    out << "}\n";
    if (!out) throw std::runtime_error("cannot write '" + args["out"] + "'");
    const TimingStats b = summarize_times(kf_bytes), t = summarize_times(kf_total), rb = summarize_times(rebuild);
    std::cout << std::setprecision(2) << "KeyFrames " << b.count << ": median " << b.median / 1024.0
              << " KB, serialize+deserialize median " << t.median << " ms; updates " << rb.count
              << ": rebuild median " << rb.median << " ms -> " << args["out"] << "\n";
  } catch (const std::exception& e) {
    std::cerr << "wire_benchmark: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
