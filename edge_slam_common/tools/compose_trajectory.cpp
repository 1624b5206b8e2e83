// The final trajectory of a split run, made the way ORB-SLAM2 and the monolithic runner save
// theirs: every frame the mobile tracked, re-anchored on the edge's final (optimised,
// loop-corrected) KeyFrame poses (data/trajectory_anchors.h).
//
//   compose_trajectory --anchors mobile_anchors.txt --keyframes edge_keyframes.txt --out trajectory.txt [--json]
//
// mobile_anchors.txt (the mobile nodelet's ~anchors_file):
//   F <stamp> <reference KF id> <T_ref_c>       a tracked frame on its reference KeyFrame
//   K <KF id> <parent KF id> <T_parent_kf>      a KeyFrame on its parent when the mobile made it
// edge_keyframes.txt (the edge nodelet's ~keyframes_file):
//   <KF id> <stamp> <T_wc>                      a Global-Map KeyFrame's final pose
//   C <KF id> <parent KF id> <T_parent_kf>      a KeyFrame Local-Mapping culled, on its parent then
// Poses are "tx ty tz qx qy qz qw"; '#' starts a comment line (io/anchors_file.h).
// A reference KeyFrame the Global-Map does not hold is reached through parents: the edge's
// relation for a culled one, the mobile's for one the edge refused (conditions 1-2). A frame
// whose chain reaches no Global-Map KeyFrame is left out and counted.
// Writes a TUM trajectory (T_wc); prints "<n> of <m> frames anchored ..." on stderr, and with
// --json {"frames": m, "anchored": n, "unanchored": m - n} on stdout. Exit 1 on bad input or
// when no frame could be anchored.
#include <iostream>
#include <map>
#include <string>

#include "edge_slam/io/anchors_file.h"
#include "edge_slam/io/output_path.h"
#include "edge_slam/io/trajectory_io.h"

using namespace edge_slam;

namespace {

int usage(const std::string& error) {
  if (!error.empty()) std::cerr << "compose_trajectory: " << error << "\n";
  std::cerr << "usage: compose_trajectory --anchors <mobile_anchors.txt> --keyframes <edge_keyframes.txt> "
               "--out <trajectory.txt> [--json]\n"
               "  every frame the mobile tracked, re-anchored on the edge's final KeyFrame poses (TUM, T_wc)\n";
  return error.empty() ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return usage("");
    if (a == "--json") {
      json = true;
      continue;
    }
    if ((a != "--anchors" && a != "--keyframes" && a != "--out") || i + 1 >= argc)
      return usage("bad argument '" + a + "'");
    args[a.substr(2)] = argv[++i];
  }
  for (const char* required : {"anchors", "keyframes", "out"})
    if (!args.count(required)) return usage(std::string("--") + required + " is required");
  try {
    const MobileAnchors mobile = read_mobile_anchors(args["anchors"]);
    const EdgeKeyFrames edge = read_edge_keyframes(args["keyframes"]);
    const ComposedTrajectory t = split_composer(mobile, edge).compose(mobile.frames);
    const size_t total = mobile.frames.size();
    std::cerr << "compose_trajectory: " << t.poses.size() << " of " << total << " frames anchored on the Global-Map ("
              << t.unanchored << " without a KeyFrame chain to it)\n";
    if (t.poses.empty()) {
      std::cerr << "compose_trajectory: no frame could be anchored on the Global-Map\n";
      return 1;
    }
    ensure_parent_directory(args["out"]);
    write_tum_trajectory(args["out"], t.poses);
    if (json)
      std::cout << "{\"frames\": " << total << ", \"anchored\": " << t.poses.size() << ", \"unanchored\": "
                << t.unanchored << "}\n";
  } catch (const std::exception& e) {
    std::cerr << "compose_trajectory: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
