// A node's live figures as (name, value) pairs, in a fixed order: computed once in the core,
// published as they are (edge_slam_msgs/Stats, bridge/stats_message.h).
#pragma once
#include <string>
#include <vector>

namespace edge_slam {

struct Figures {
  std::vector<std::string> names;
  std::vector<double> values;
  Figures& add(const std::string& name, double value) {
    names.push_back(name);
    values.push_back(value);
    return *this;
  }
  Figures& add(const Figures& more) {
    names.insert(names.end(), more.names.begin(), more.names.end());
    values.insert(values.end(), more.values.begin(), more.values.end());
    return *this;
  }
};

}  // namespace edge_slam
