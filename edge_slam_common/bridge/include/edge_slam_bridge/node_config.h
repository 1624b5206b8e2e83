// What both nodelets load at start: the camera and SLAM configuration files and the BoW
// vocabulary, named by the private parameters ~camera_config, ~slam_config and ~vocabulary.
// Both files are checked whole (module/slam_config.h): a bad value is refused, a key no loader
// knows is warned about with the nearest known one.
#pragma once
#include <edge_slam/camera/camera_loader.h>
#include <edge_slam/data/bow_vocabulary.h>
#include <edge_slam/io/config_file.h>
#include <edge_slam/io/vocabulary_io.h>
#include <edge_slam/module/slam_config.h>
#include <ros/ros.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace edge_slam {

struct NodeConfig {
  ConfigMap slam;
  PinholeCamera camera;
  std::shared_ptr<const BowVocabulary> vocabulary;
};

// Throws std::runtime_error naming the missing parameter or the file that failed to load.
inline NodeConfig load_node_config(const ros::NodeHandle& pnh) {
  auto path = [&pnh](const std::string& name) {
    std::string value;
    if (!pnh.getParam(name, value) || value.empty())
      throw std::runtime_error("parameter ~" + name + " (a file path) is required");
    return value;
  };
  const std::string camera_path = path("camera_config"), slam_path = path("slam_config");
  const std::string vocabulary_path = path("vocabulary");
  NodeConfig c;
  c.slam = ConfigMap::load(slam_path);
  check_slam_config(c.slam);
  const ConfigMap camera = ConfigMap::load(camera_path);
  c.camera = load_camera(camera);
  warn_unknown_keys(camera);
  ROS_INFO("loading vocabulary %s", vocabulary_path.c_str());
  c.vocabulary = std::make_shared<const BowVocabulary>(load_vocabulary(vocabulary_path));
  return c;
}

}  // namespace edge_slam
