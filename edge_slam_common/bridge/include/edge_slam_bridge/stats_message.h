// The core's figures (util/figures.h) as the ~stats message both nodelets publish.
#pragma once
#include <edge_slam/util/figures.h>
#include <edge_slam_msgs/Stats.h>
#include <ros/time.h>

#include <string>

namespace edge_slam {

inline edge_slam_msgs::Stats to_message(const Figures& f, const std::string& node, const ros::Time& stamp) {
  edge_slam_msgs::Stats m;
  m.header.stamp = stamp;
  m.node = node;
  m.names = f.names;
  m.values = f.values;
  return m;
}

}  // namespace edge_slam
