// A message's serialised size: what it costs on the wire (the figures count these bytes).
#pragma once
#include <ros/serialization.h>

#include <cstddef>

namespace edge_slam {

template <typename M>
size_t wire_size(const M& msg) {
  return ros::serialization::serializationLength(msg);
}

}  // namespace edge_slam
