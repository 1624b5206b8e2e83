// Routes the core's log (util/log.h) to rosconsole under the nodelet's name, so the core's lines
// show with the node's own, at their level (NODELET_DEBUG/INFO/WARN/ERROR alike). One sink per
// process: call it from the nodelet's onInit.
#pragma once
#include <edge_slam/util/log.h>
#include <ros/console.h>

#include <string>

namespace edge_slam {

inline void route_core_log_to_rosconsole(const std::string& name) {
  set_log_sink([name](LogLevel level, const std::string& message) {
    switch (level) {
      case LogLevel::kDebug: ROS_DEBUG_NAMED(name, "%s", message.c_str()); break;
      case LogLevel::kInfo: ROS_INFO_NAMED(name, "%s", message.c_str()); break;
      case LogLevel::kWarn: ROS_WARN_NAMED(name, "%s", message.c_str()); break;
      case LogLevel::kError: ROS_ERROR_NAMED(name, "%s", message.c_str()); break;
    }
  });
}

}  // namespace edge_slam
