// The Global-Map on disk (edge persistence): a versioned binary file holding a MapSnapshot.
// Layout: magic "ESMAPBIN", u32 version, u32 zero, u64 payload size, u64 FNV-1a of the
// payload, then the payload (little-endian; the id counters; KeyFrames with pose, camera,
// features, descriptors, observations, parent, covisibility weights and loop edges; map
// points; the KeyFrame accounting; since version 2, with several mobiles, each robot's
// deliveries and accounting and where each of its maps sits (module/robot_frames.h); since
// version 3, the merges of their maps so far; since version 4, the loop detector's history).
// Versions 1 (one robot), 2 and 3 are still read.
// Writing goes to a temporary file in the same folder which is then renamed over the target, so
// a crash mid-write leaves the previous file intact.
#pragma once
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "edge_slam/io/wire_records.h"

namespace edge_slam {

// 2: the several-robot sections; 3: the merge history; 4: the loop detector's history (1-3 still read)
inline constexpr uint32_t kMapFileVersion = 4;

// One robot's deliveries on an edge serving several mobiles: as MapSnapshot's own fields are
// for the one robot.
struct RobotMapSection {
  uint64_t last_keyframe_seq = 0;
  std::vector<uint32_t> received_keyframe_ids, inserted_keyframe_ids;
};
// Where the maps are (module/robot_frames.h): robot `robot`'s KeyFrames from `first_id` on
// were made in a map now in group `group`'s coordinates (at T_group_epoch) ...
struct MapEpochRecord {
  uint32_t robot = 0, first_id = 0;
  int32_t group = 0;
  Eigen::Isometry3d T_group_epoch = Eigen::Isometry3d::Identity();
};
// ... and group k sits in the world at T_world_group (unset: not joined with robot 0's first
// map), or was merged into another.
struct MapGroupRecord {
  std::optional<Eigen::Isometry3d> T_world_group;
  bool merged_away = false;
};

// One merge of two robots' maps (module/loop_closing.h MergeEvent without its correction
// figures): KeyFrame `keyframe` (group_from) matched `loop_keyframe` (group_into) with `matches`
// inliers, and group_from went into group_into at T_into_from. A restored edge still reports
// the merges made before its restart (metrics.json, ~stats maps_merged).
struct MapMergeRecord {
  uint32_t keyframe = 0, loop_keyframe = 0;
  int32_t group_from = 0, group_into = 0, matches = 0;
  Eigen::Isometry3d T_into_from = Eigen::Isometry3d::Identity();
};

// The loop detector's history (module/loop_detector.h), so that a restored edge neither forgets
// a run of consistent detections it was about to close a loop with nor closes one right after
// the last: robot `robot`'s candidate groups, each with its consistency count ...
struct LoopGroupRecord {
  uint32_t robot = 0;
  int32_t consistency = 0;
  std::vector<uint32_t> members;  // KeyFrame ids
};
// ... and, per robot, its newest KeyFrame seen by the detector and its newest at the last loop
// (no detection until min_keyframes_after_loop more of its own).
struct LoopRobotRecord {
  uint32_t robot = 0;
  std::optional<uint32_t> newest_keyframe, last_loop_keyframe;
};

struct MapSnapshot {
  // Every KeyFrame (observations of all its points, parent, covisibility weights) and every
  // map point; checked on load like a Local-Map update (io/record_checks.h).
  MapUpdateRecord content;
  std::unordered_map<uint32_t, std::vector<uint32_t>> loop_edges;  // KeyFrame id -> loop partners
  uint32_t next_keyframe_id = 0, next_map_point_id = 0;             // the map's id allocators
  uint64_t last_keyframe_seq = 0;                                   // delivery acknowledgement
  // The edge's KeyFrame accounting, so a restarted edge still de-duplicates and can account
  // for every KeyFrame the mobile sent: ids received, inserted, and culled since.
  std::vector<uint32_t> received_keyframe_ids, inserted_keyframe_ids, culled_keyframe_ids;
  // Several mobiles (empty with one, whose deliveries are the fields above): robot r's
  // deliveries in robots[r], and every robot's maps and their groups.
  std::vector<RobotMapSection> robots;
  std::vector<MapEpochRecord> epochs;
  std::vector<MapGroupRecord> groups;
  std::vector<MapMergeRecord> merges;  // oldest first
  std::vector<LoopGroupRecord> loop_groups;  // robots: 0 with one robot, else an index of `robots`
  std::vector<LoopRobotRecord> loop_robots;
};

std::vector<uint8_t> encode_map_file(const MapSnapshot& snapshot);
// Throws std::runtime_error naming `origin` and what is wrong (magic, version, size, checksum,
// truncation, or a record that fails its checks).
MapSnapshot decode_map_file(const uint8_t* data, size_t size, const std::string& origin);

void write_map_file(const MapSnapshot& snapshot, const std::string& path);  // atomic; throws
MapSnapshot read_map_file(const std::string& path);                         // throws

}  // namespace edge_slam
