// Where each robot's map sits when one edge serves several mobiles (issue #16). The edge keeps
// one Global-Map; before two robots are known to have seen the same place their KeyFrames form
// separate components of it, each stored in the coordinates of the map it started (a "group").
// A merge (module/loop_closing.h) moves one group's KeyFrames and points into another's
// coordinates; from then on both are one group.
//   - every robot works in its own frame `robotN/map` (the mobile's Local-Map): the edge turns
//     received records into the group's coordinates with T_group_robot and updates back;
//   - "world" is the frame robot 0's first map started in; a group has a place in the world
//     once it contains that map (then TF world -> robotN/map = T_world_group * T_group_robot).
// A robot that resets (its Local-Map cleared) starts a new map: an "epoch" with a group of its
// own, the old KeyFrames staying where they are (they go on serving the others).
// Thread-safe; a leaf lock (never held while taking another).
#pragma once
#include <Eigen/Geometry>

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "edge_slam/io/map_file.h"
#include "edge_slam/io/wire_records.h"

namespace edge_slam {

struct RobotPlacement {
  int group = 0;
  Eigen::Isometry3d T_group_robot = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> T_world_robot;  // unset until the group is placed in the world
};

class RobotFrames {
 public:
  explicit RobotFrames(int robots);

  int robots() const { return static_cast<int>(epochs_.size()); }
  // The group of the map this KeyFrame was made in (by the robot and epoch its id names);
  // -1 for an id of no configured robot.
  int group_of(uint32_t kf_id) const;
  RobotPlacement placement(int robot) const;  // of the robot's current map
  // The robot's map was cleared: KeyFrames with ids >= first_new_id start a new group.
  void start_new_map(int robot, uint32_t first_new_id);
  // Group `from` was moved into group `into`'s coordinates by T_into_from: every map in it
  // follows. Returns false (and changes nothing) when from == into or either is unknown.
  bool merge(int from, int into, const Eigen::Isometry3d& T_into_from);
  // Where the group's coordinates sit in the world (unset: not joined with robot 0's first map).
  std::optional<Eigen::Isometry3d> T_world_group(int group) const;
  // Each robot's frame stays attached to the oldest KeyFrame of its map in the Global-Map (its
  // anchor; kept while it stays in the map): after the Global-Map moved under it (a loop
  // correction, a full BA), T_group_robot follows the anchor so that the anchor keeps its pose in
  // the robot's frame, and the world (robot 0's first map) follows robot 0's first anchor. Else
  // an optimisation holding another robot's KeyFrame fixed (a loop between two robots' maps)
  // shifts a robot's whole map, and each update to it afterwards makes its pose jump.
  // T_cw: every KeyFrame's pose in its group's coordinates, by id. Epochs without an anchor
  // (new, or theirs left the map) take their oldest KeyFrame at its pose now.
  void follow_anchors(const std::map<uint32_t, Eigen::Isometry3d>& T_cw);
  // Persistence (io/map_file.h): every robot's maps and their groups, and back. restore()
  // checks first (each robot of robots() has its first map, ids ascending, groups known) and
  // changes nothing when they do not fit, with the reason in *error.
  void save_to(std::vector<MapEpochRecord>& epochs, std::vector<MapGroupRecord>& groups) const;
  bool restore(const std::vector<MapEpochRecord>& epochs, const std::vector<MapGroupRecord>& groups,
               std::string* error);

 private:
  struct Anchor {
    uint32_t id;
    Eigen::Isometry3d T_cw;  // in the group's coordinates, when last followed
  };
  struct Epoch {
    uint32_t first_id;  // KeyFrames of this robot from this id on
    int group;
    Eigen::Isometry3d T_group_epoch;
    std::optional<Anchor> anchor = std::nullopt;
  };
  struct Group {
    std::optional<Eigen::Isometry3d> T_world_group;
    bool merged_away = false;
  };
  const Epoch* epoch_of(uint32_t kf_id) const;

  mutable std::mutex mutex_;
  std::vector<std::vector<Epoch>> epochs_;  // per robot, by first_id ascending
  std::vector<Group> groups_;
};

// A KeyFrame record moved by T (its pose and the points it creates), an update's KeyFrames and
// points the same way: between a robot's frame and its group's coordinates.
void transform_record(KeyFrameRecord& r, const Eigen::Isometry3d& T);
void transform_update(MapUpdateRecord& u, const Eigen::Isometry3d& T);

}  // namespace edge_slam
