// Every parameter the loaders read is refused at start when out of range (or not a number),
// with an error naming the key and the valid range (so a nodelet refuses to start with a message
// saying what to fix); a value at the edge of the range loads. A key may have several rows:
// one per kind of bad value (below, above, not a number).
#include <gtest/gtest.h>

#include <functional>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/tracking_params.h"

namespace edge_slam {
namespace {

const char* kCamera =
    "camera:\n  name: test\n  width: 640\n  height: 480\n  fx: 500.0\n  fy: 500.0\n  cx: 319.5\n"
    "  cy: 239.5\n  bf: 40.0\n  th_depth: 40.0\n  depth_factor: 5000\n";

struct Case {
  const char* key;
  const char* bad;   // just outside the range (or malformed)
  const char* good;  // at the edge of the range
  const char* range; // as the error prints it
};

using Loader = std::function<void(const ConfigMap&)>;

void check(const std::vector<Case>& cases, const Loader& load, const std::string& base = "") {
  for (const Case& c : cases) {
    ConfigMap cfg = ConfigMap::parse(base, "p.yaml");
    cfg.set(c.key, c.good);
    EXPECT_NO_THROW(load(cfg)) << c.key << " = " << c.good;
    cfg.set(c.key, c.bad);
    std::string error;
    try {
      load(cfg);
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
    EXPECT_NE(error.find(std::string("'") + c.key + "'"), std::string::npos) << c.key << ": " << error;
    EXPECT_NE(error.find(c.range), std::string::npos) << c.key << ": " << error;
  }
}

TEST(ParameterRanges, Tracking) {
  check({{"orb/num_features", "49", "50", "[50, 100000]"},
         {"orb/num_features", "0", "100000", "[50, 100000]"},
         {"orb/num_features", "-5", "50", "[50, 100000]"},
         {"orb/scale_factor", "1.0", "4", "[1.01, 4]"},
         {"orb/num_levels", "33", "1", "[1, 32]"},
         {"orb/num_levels", "0", "32", "[1, 32]"},
         {"orb/ini_fast_threshold", "0", "255", "[1, 255]"},
         {"orb/min_fast_threshold", "256", "1", "[1, 255]"},
         {"tracking/min_frames_after_relocalization", "-1", "0", "[0, 100000]"},
         {"tracking/max_frames_between_keyframes", "0", "1", "[1, 100000]"},
         {"tracking/min_tracked_points", "-1", "0", "[0, 100000]"},
         {"tracking/ref_ratio", "nan", "1", "[0, 1]"},
         {"tracking/close_points_tracked", "-1", "0", "[0, 100000]"},
         {"tracking/close_points_new", "100001", "100000", "[0, 100000]"},
         {"tracking/new_points_per_keyframe", "-1", "0", "[0, 100000]"},
         {"tracking/min_initial_keypoints", "0", "1", "[1, 100000]"},
         {"tracking/min_inliers", "2", "3", "[3, 100000]"},
         {"tracking/min_inliers_after_relocalization", "2", "3", "[3, 100000]"},
         {"tracking/reference_min_observations", "1001", "1000", "[1, 1000]"},
         {"tracking/max_local_keyframes", "0", "1", "[1, 100000]"},
         {"tracking/keyframe_conditions", "some", "edge", "all, mobile, edge"}},
        [](const ConfigMap& c) {
          load_orb_params(c);
          load_tracking_params(c);
        });
}

TEST(ParameterRanges, MobileAndEdgeSessions) {
  check({{"edge_slam/initial_time_constraint", "61", "60", "[0, 60]"},
         {"edge_slam/initial_time_constraint", "-0.1", "0", "[0, 60]"},
         {"edge_slam/update_size", "0", "1000", "[1, 1000]"},
         {"edge_slam/local_map_cap", "0", "6", "[6, 100000]"},  // the lower bound is update_size (6)
         {"edge_slam/local_map_cap", "5", "40", "[6, 100000]"},
         {"edge_slam/relocalization_frame_period", "-0.1", "0", "[0, 60]"},
         {"edge_slam/relocalization_frame_period", "-2", "60", "[0, 60]"}},
        [](const ConfigMap& c) { load_mobile_session_params(c); });
  check({{"edge_slam/update_size", "1001", "1", "[1, 1000]"},
         {"edge_slam/update_size", "0", "1000", "[1, 1000]"},
         {"edge_slam/update_period", "-1", "0.05", "[0.05, 3600]"},
         {"edge_slam/update_period", "nan", "2.5", "[0.05, 3600]"},
         {"edge_slam/local_map_cap", "0", "6", "[6, 100000]"},
         {"tracking/min_frames_after_relocalization", "inf", "100000", "[0, 100000]"},
         {"tracking/max_frames_between_keyframes", "0", "1", "[1, 100000]"}},
        [](const ConfigMap& c) { load_edge_session_params(c); });
}

TEST(ParameterRanges, Camera) {
  check({{"camera/width", "0", "1", "[1, 100000]"},
         {"camera/height", "100001", "100000", "[1, 100000]"},
         {"camera/fx", "0", "1e7", "[1e-06, 1e+07]"},
         {"camera/fy", "-500", "500", "[1e-06, 1e+07]"},
         {"camera/cx", "2e6", "-1e6", "[-1e+06, 1e+06]"},
         {"camera/cy", "x", "0", "[-1e+06, 1e+06]"},
         {"camera/k1", "101", "-100", "[-100, 100]"},
         {"camera/k2", "-101", "100", "[-100, 100]"},
         {"camera/p1", "nan", "0", "[-100, 100]"},
         {"camera/p2", "1e3", "0", "[-100, 100]"},
         {"camera/k3", "-1e3", "0", "[-100, 100]"},
         {"camera/fps", "0.01", "0.1", "[0.1, 10000]"},
         {"camera/bf", "0", "40", "[1e-09, 1e+07]"},
         {"camera/th_depth", "0", "1e6", "[1e-06, 1e+06]"},
         {"camera/depth_factor", "-5000", "1", "[1e-09, 1e+09]"},
         {"camera/rgb_encoding", "yuv", "rgb8", "rgb8, bgr8"}},
        [](const ConfigMap& c) { load_camera(c); }, kCamera);
}

}  // namespace
}  // namespace edge_slam
