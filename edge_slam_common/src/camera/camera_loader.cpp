#include "edge_slam/camera/camera_loader.h"

#include <stdexcept>

namespace edge_slam {

PinholeCamera load_camera(const ConfigMap& cfg) {
  PinholeCamera cam;
  cam.name = cfg.get_string("camera/name", "camera");
  cam.width = cfg.get_int("camera/width", 1, 100000);
  cam.height = cfg.get_int("camera/height", 1, 100000);
  cam.fx = cfg.get_double("camera/fx", 1e-6, 1e7);
  cam.fy = cfg.get_double("camera/fy", 1e-6, 1e7);
  cam.cx = cfg.get_double("camera/cx", -1e6, 1e6);
  cam.cy = cfg.get_double("camera/cy", -1e6, 1e6);
  cam.k1 = cfg.get_double_or("camera/k1", 0.0, -100, 100);
  cam.k2 = cfg.get_double_or("camera/k2", 0.0, -100, 100);
  cam.p1 = cfg.get_double_or("camera/p1", 0.0, -100, 100);
  cam.p2 = cfg.get_double_or("camera/p2", 0.0, -100, 100);
  cam.k3 = cfg.get_double_or("camera/k3", 0.0, -100, 100);
  cam.fps = cfg.get_double_or("camera/fps", 30.0, 0.1, 10000);
  // Negative: bottom row first. At most one second (a readout is shorter than a frame period).
  cam.rolling_shutter_readout = cfg.get_double_or("camera/rolling_shutter_readout", 0.0, -1.0, 1.0);
  cam.bf = cfg.get_double("camera/bf", 1e-9, 1e7);
  const double th_depth_baselines = cfg.get_double("camera/th_depth", 1e-6, 1e6);
  cam.th_depth = th_depth_baselines * cam.bf / cam.fx;
  cam.depth_factor = cfg.get_double("camera/depth_factor", 1e-9, 1e9);
  load_rgb_encoding(cfg);  // validate early
  return cam;
}

PinholeCamera load_camera(const std::string& yaml_path) {
  return load_camera(ConfigMap::load(yaml_path));
}

RgbEncoding load_rgb_encoding(const ConfigMap& cfg) {
  const std::string enc = cfg.get_string("camera/rgb_encoding", "bgr8");
  if (enc == "bgr8" || enc == "bgr") return RgbEncoding::kBgr;
  if (enc == "rgb8" || enc == "rgb") return RgbEncoding::kRgb;
  throw std::runtime_error(cfg.origin() + ": key 'camera/rgb_encoding' has value '" + enc +
                           "', expected one of rgb8, bgr8");
}

}  // namespace edge_slam
