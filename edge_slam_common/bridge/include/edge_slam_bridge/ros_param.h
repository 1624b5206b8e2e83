// A node's own ROS parameters read with a valid range: a value outside it is refused at start
// with the parameter's name, its value and the range (the nodelet logs it and does not start)
// instead of surfacing later as a stall, a crash or an unbounded buffer.
#pragma once
#include <ros/ros.h>

#include <sstream>
#include <stdexcept>
#include <string>

namespace edge_slam {

template <typename T>
T param_in_range(const ros::NodeHandle& pnh, const std::string& name, T def, T min, T max) {
  T value = def;
  pnh.param(name, value, def);
  if (!(value >= min && value <= max)) {  // also refuses NaN
    std::ostringstream s;
    s << "parameter ~" << name << " = " << value << " is outside the valid range [" << min << ", " << max << "]";
    throw std::runtime_error(s.str());
  }
  return value;
}

}  // namespace edge_slam
