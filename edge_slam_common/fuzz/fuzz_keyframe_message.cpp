// Fuzz target: bytes -> edge_slam_msgs::KeyFrame -> KeyFrameRecord -> the edge's KeyFrame and
// new points -> a map holding them (what EdgeSession::receive_keyframe does with a message).
#include <edge_slam/data/map.h>
#include <edge_slam/io/map_records.h>
#include <edge_slam_bridge/checked_deserialization.h>

#include "fuzz_support.h"

using namespace edge_slam;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  edge_slam_msgs::KeyFrame msg;
  if (!deserialize_checked(data, size, msg, fuzz::limits()).ok) return 0;
  KeyFrameRecord record;
  if (!from_message(msg, record, fuzz::limits()).ok) return 0;
  std::shared_ptr<KeyFrame> kf;
  std::vector<std::shared_ptr<MapPoint>> points;
  try {
    kf = keyframe_from_record(record, fuzz::camera(), fuzz::pyramid());
    for (const NewPointRecord& p : record.new_points) points.push_back(map_point_from_new_point(p, *kf));
  } catch (const std::invalid_argument&) {
    return 0;  // e.g. a camera other than the receiver's: rejected with a reason
  }
  kf->compute_bow(*fuzz::vocabulary());
  Map map;
  for (const auto& mp : points) map.add_map_point(mp);
  map.add_keyframe(kf);
  const std::vector<uint32_t> ids = kf->map_point_ids();
  for (size_t i = 0; i < ids.size(); ++i)
    if (auto mp = map.map_point(ids[i])) mp->add_observation(kf->id(), static_cast<int>(i));
  for (const auto& mp : points) {
    mp->update_normal_and_depth(map);
    mp->update_descriptor(map);
  }
  kf->update_connections(map);
  kf->features_in_area(320, 240, 100);
  return 0;
}
