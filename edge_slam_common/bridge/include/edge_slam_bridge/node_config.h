// What both nodelets load at start: the camera and SLAM configuration files and the BoW
// vocabulary, named by the private parameters ~camera_config, ~slam_config and ~vocabulary.
#pragma once
#include <edge_slam/camera/camera_loader.h>
#include <edge_slam/data/bow_vocabulary.h>
#include <edge_slam/io/config_file.h>
#include <edge_slam/io/vocabulary_io.h>
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
  c.camera = load_camera(ConfigMap::load(camera_path));
  ROS_INFO("loading vocabulary %s", vocabulary_path.c_str());
  c.vocabulary = std::make_shared<const BowVocabulary>(load_vocabulary(vocabulary_path));
  return c;
}

}  // namespace edge_slam
