// Fuzz target: bytes -> edge_slam_msgs::Frame -> FrameRecord -> Frame with BoW (what the edge
// builds from a relocalization request before querying its KeyFrame database).
#include <edge_slam/data/frame.h>
#include <edge_slam/io/map_records.h>
#include <edge_slam_bridge/checked_deserialization.h>

#include "fuzz_support.h"

using namespace edge_slam;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  edge_slam_msgs::Frame msg;
  if (!deserialize_checked(data, size, msg, fuzz::limits()).ok) return 0;
  FrameRecord record;
  if (!from_message(msg, record, fuzz::limits()).ok) return 0;
  try {
    Frame frame(record.id, record.stamp,
                features_from_record(record.features, record.camera, fuzz::camera(), fuzz::pyramid()));
    frame.compute_bow(*fuzz::vocabulary());
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
