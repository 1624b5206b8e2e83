// Local-Mapping settings: the "local_mapping:" section of config/slam.yaml, where each one is
// documented. Defaults are ORB-SLAM2's (LocalMapping.cc, Optimizer::LocalBundleAdjustment).
#pragma once
#include <cstddef>

#include "edge_slam/io/config_file.h"
#include "edge_slam/module/keyframe_culling.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "edge_slam/module/map_point_culling.h"
#include "edge_slam/module/triangulation.h"

namespace edge_slam {

struct LocalMappingParams {
  MapPointCullingParams point_culling;
  TriangulationParams triangulation;
  KeyFrameCullingParams keyframe_culling;
  bool local_ba = true;
  int ba_first_pass_iterations = 5;   // with the Huber kernel
  int ba_second_pass_iterations = 10; // after dropping outliers
  int ba_num_threads = 1;
  LocalBaWindow ba_window;  // bounds on the local BA window; {0, 0} = ORB-SLAM2's unbounded window
  bool cull_keyframes = true;
  size_t queue_capacity = 1000;  // large: an evicted keyframe would never be processed
};

// Reads the "local_mapping:" section; absent keys keep the defaults, bad values throw with
// the file and key named.
LocalMappingParams load_local_mapping_params(const ConfigMap& cfg);

}  // namespace edge_slam
