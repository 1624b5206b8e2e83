// The synthetic room's camera and the project's camera YAML format (config/camera_*.yaml).
#pragma once
#include "edge_slam/camera/pinhole_camera.h"

#include <string>

namespace edge_slam {

// 640x480, fx = fy = 525, cx = 319.5, cy = 239.5, no distortion, bf = 40 (as ORB-SLAM2's
// TUM1.yaml), th_depth = 40 baselines, depth factor 5000 (TUM).
PinholeCamera synthetic_room_camera(double fps = 30.0);

// The camera as the project's YAML: a top-level `camera:` map with documented scalar keys.
// Note th_depth is written in baselines (ORB-SLAM2's ThDepth), i.e. camera.th_depth * fx / bf.
std::string camera_yaml(const PinholeCamera& camera, const std::string& title_comment,
                        const std::string& rgb_encoding = "rgb8");

}  // namespace edge_slam
