// config/slam.yaml as a whole. It is one file for the monolithic runner, the mobile and the
// edge, each of which reads only its own sections, so no single process would notice a key that
// none of them knows. check_slam_config() runs the loader of every section on it: a bad value
// anywhere is refused at start (std::runtime_error naming the key and range), and every key no
// loader asked for is warned about once, with the nearest known key (io/config_file.h). The
// known keys are exactly what the loaders read: there is no list to keep.
#pragma once
#include <string>

#include "edge_slam/io/config_file.h"

namespace edge_slam {

// What only the runners read: vocabulary/path (relative to the repository root; the nodelets
// get theirs as a parameter) and loop_closing/final_full_ba_iterations.
struct RunnerSettings {
  std::string vocabulary_path;
  int final_full_ba_iterations = 0;
};
RunnerSettings load_runner_settings(const ConfigMap& cfg);

void check_slam_config(const ConfigMap& slam);

}  // namespace edge_slam
