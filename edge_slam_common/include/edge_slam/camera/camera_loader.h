// Builds a PinholeCamera from the "camera:" section of a config file.
#pragma once
#include <string>

#include "edge_slam/camera/pinhole_camera.h"
#include "edge_slam/io/config_file.h"

namespace edge_slam {

// Colour encoding of incoming images; RGB vs BGR only matters for the grey conversion.
enum class RgbEncoding { kBgr, kRgb };

// Reads camera/{name,width,height,fx,fy,cx,cy,k1,k2,p1,p2,k3,fps,bf,th_depth,depth_factor}.
// th_depth is given in baselines (ORB-SLAM2 ThDepth) and converted to metres:
// th_depth_m = th_depth * bf / fx. Throws std::runtime_error naming the bad key.
PinholeCamera load_camera(const ConfigMap& cfg);
PinholeCamera load_camera(const std::string& yaml_path);
RgbEncoding load_rgb_encoding(const ConfigMap& cfg);  // camera/rgb_encoding: rgb8|bgr8

}  // namespace edge_slam
