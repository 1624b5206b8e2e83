#include "edge_slam/sim/synthetic_camera.h"

#include <algorithm>
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
  // The virtual baseline weighs the depth residual of every pose and BA cost (u - bf / z has
  // bf / z^2 px per metre of depth). ORB-SLAM2's Kinect value, 40, trusts depth to ~Z^2 / 40 m
  // per pixel of noise (22 cm at 3 m); this renderer's depth is exact to 0.2 mm, and with that
  // weight a KeyFrame made in the look-away turn was turned 0.6 degrees by local BA along the
  // rotation/translation ambiguity of a wall seen from a short baseline (README, depth weight).
  // 400 trusts it to 2.2 cm at 3 m; the close/far threshold stays 3.05 m (4 baselines).
  c.bf = 400.0;
  c.th_depth = 4.0 * c.bf / c.fx;
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
  struct Key { const char* name; std::string value; const char* comment; };
  const Key keys[] = {
      {"name", c.name, "identifies the calibration"},
      {"width", std::to_string(c.width), "image width (pixels)"},
      {"height", std::to_string(c.height), "image height (pixels)"},
      {"fx", yaml_float(c.fx), "focal length x (pixels)"},
      {"fy", yaml_float(c.fy), "focal length y (pixels)"},
      {"cx", yaml_float(c.cx), "principal point x (pixels)"},
      {"cy", yaml_float(c.cy), "principal point y (pixels)"},
      {"k1", yaml_float(c.k1), "radial distortion (OpenCV radial-tangential model)"},
      {"k2", yaml_float(c.k2), "radial distortion"},
      {"p1", yaml_float(c.p1), "tangential distortion"},
      {"p2", yaml_float(c.p2), "tangential distortion"},
      {"k3", yaml_float(c.k3), "radial distortion"},
      {"fps", yaml_float(c.fps), "frame rate (Hz)"},
      {"rolling_shutter_readout", yaml_float(c.rolling_shutter_readout),
       "s from the top row's exposure to the bottom row's; 0 = global shutter (the renderer)"},
      {"bf", yaml_float(c.bf), "virtual stereo baseline (m) * fx; weighs depth (ORB-SLAM2's Kinect: 40)"},
      {"th_depth", yaml_float(c.bf > 0 ? c.th_depth * c.fx / c.bf : 0.0),
       "close/far threshold in baselines (ORB-SLAM2 ThDepth): th_depth * bf / fx metres"},
      {"depth_factor", yaml_float(c.depth_factor), "16UC1 depth value / depth_factor = metres"},
      {"rgb_encoding", enc, "encoding of the colour image topic"},
  };
  std::ostringstream y;
  y << "# " << title << "\ncamera:\n";
  for (const Key& k : keys) {
    std::string line = std::string("  ") + k.name + ": " + k.value;
    line.resize(std::max<size_t>(line.size() + 2, 24), ' ');
    y << line << "# " << k.comment << "\n";
  }
  return y.str();
}

}  // namespace edge_slam
