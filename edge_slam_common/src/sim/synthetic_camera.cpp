#include "edge_slam/sim/synthetic_camera.h"

#include <cstdio>
#include <sstream>

namespace edge_slam {

PinholeCamera synthetic_room_camera(double fps) {
  PinholeCamera c;
  c.name = "synthetic_room";
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 525.0;
  c.cx = 319.5;
  c.cy = 239.5;
  c.bf = 40.0;
  c.th_depth = 40.0 * c.bf / c.fx;
  c.depth_factor = 5000.0;
  c.fps = fps;
  return c;
}

namespace {
// Shortest text (<= 12 significant digits, hiding float dust), always with a decimal point so YAML reads a float.
std::string yaml_float(double x) {
  char buf[64];
  for (int precision = 6; precision <= 12; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, x);
    if (std::stod(buf) == x) break;
  }
  std::string s(buf);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}
}  // namespace

std::string camera_yaml(const PinholeCamera& c, const std::string& title, const std::string& enc) {
  std::ostringstream y;
  y << "# " << title << "\n"
    << "camera:\n"
    << "  name: " << c.name << "            # identifies the calibration\n"
    << "  width: " << c.width << "            # image size (pixels)\n"
    << "  height: " << c.height << "\n"
    << "  fx: " << yaml_float(c.fx) << "            # focal lengths (pixels)\n"
    << "  fy: " << yaml_float(c.fy) << "\n"
    << "  cx: " << yaml_float(c.cx) << "            # principal point (pixels)\n"
    << "  cy: " << yaml_float(c.cy) << "\n"
    << "  k1: " << yaml_float(c.k1) << "            # OpenCV radial-tangential distortion\n"
    << "  k2: " << yaml_float(c.k2) << "\n"
    << "  p1: " << yaml_float(c.p1) << "\n"
    << "  p2: " << yaml_float(c.p2) << "\n"
    << "  k3: " << yaml_float(c.k3) << "\n"
    << "  fps: " << yaml_float(c.fps) << "            # frame rate (Hz)\n"
    << "  bf: " << yaml_float(c.bf) << "           # virtual stereo baseline (m) * fx, as ORB-SLAM2's TUM1.yaml\n"
    << "  th_depth: " << yaml_float(c.bf > 0 ? c.th_depth * c.fx / c.bf : 0.0)
    << "     # close/far threshold in baselines (ORB-SLAM2 ThDepth): th_depth * bf / fx metres\n"
    << "  depth_factor: " << yaml_float(c.depth_factor) << "  # 16UC1 depth value / depth_factor = metres\n"
    << "  rgb_encoding: " << enc << "    # colour image encoding (sensor_msgs/Image)\n";
  return y.str();
}

}  // namespace edge_slam
