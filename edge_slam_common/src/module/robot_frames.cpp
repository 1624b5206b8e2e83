#include "edge_slam/module/robot_frames.h"

#include "edge_slam/util/robot_ids.h"

namespace edge_slam {

RobotFrames::RobotFrames(int robots) : epochs_(static_cast<size_t>(std::max(1, robots))) {
  for (size_t r = 0; r < epochs_.size(); ++r) {
    epochs_[r].push_back(Epoch{keyframe_id_space(static_cast<int>(r)).first, static_cast<int>(r),
                               Eigen::Isometry3d::Identity()});
    groups_.push_back(Group{});
  }
  groups_[0].T_world_group = Eigen::Isometry3d::Identity();  // world: robot 0's first map
}

const RobotFrames::Epoch* RobotFrames::epoch_of(uint32_t kf_id) const {
  const int robot = robot_of_keyframe(kf_id);
  if (robot < 0 || robot >= static_cast<int>(epochs_.size())) return nullptr;
  const auto& list = epochs_[robot];
  for (auto it = list.rbegin(); it != list.rend(); ++it)
    if (kf_id >= it->first_id) return &*it;
  return &list.front();
}

int RobotFrames::group_of(uint32_t kf_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const Epoch* e = epoch_of(kf_id);
  return e ? e->group : -1;
}

RobotPlacement RobotFrames::placement(int robot) const {
  std::lock_guard<std::mutex> lock(mutex_);
  RobotPlacement p;
  if (robot < 0 || robot >= static_cast<int>(epochs_.size())) return p;
  const Epoch& e = epochs_[robot].back();
  p.group = e.group;
  p.T_group_robot = e.T_group_epoch;
  if (groups_[e.group].T_world_group) p.T_world_robot = *groups_[e.group].T_world_group * e.T_group_epoch;
  return p;
}

std::optional<Eigen::Isometry3d> RobotFrames::T_world_group(int group) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (group < 0 || group >= static_cast<int>(groups_.size())) return std::nullopt;
  return groups_[group].T_world_group;
}

void RobotFrames::start_new_map(int robot, uint32_t first_new_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (robot < 0 || robot >= static_cast<int>(epochs_.size())) return;
  auto& list = epochs_[robot];
  if (first_new_id <= list.back().first_id) return;  // nothing made in the current map yet
  groups_.push_back(Group{});
  list.push_back(Epoch{first_new_id, static_cast<int>(groups_.size()) - 1, Eigen::Isometry3d::Identity()});
}

bool RobotFrames::merge(int from, int into, const Eigen::Isometry3d& T_into_from) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int n = static_cast<int>(groups_.size());
  if (from == into || from < 0 || into < 0 || from >= n || into >= n) return false;
  if (groups_[from].merged_away || groups_[into].merged_away) return false;
  for (auto& list : epochs_)
    for (Epoch& e : list)
      if (e.group == from) {
        e.group = into;
        e.T_group_epoch = T_into_from * e.T_group_epoch;
        if (e.anchor) e.anchor->T_cw = e.anchor->T_cw * T_into_from.inverse();  // moved with its map
      }
  // The world stays where it was: if only the moved group was placed, the host now is too.
  if (!groups_[into].T_world_group && groups_[from].T_world_group)
    groups_[into].T_world_group = *groups_[from].T_world_group * T_into_from.inverse();
  groups_[from].merged_away = true;
  return true;
}

void RobotFrames::follow_anchors(const std::map<uint32_t, Eigen::Isometry3d>& T_cw) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (size_t r = 0; r < epochs_.size(); ++r) {
    auto& list = epochs_[r];
    for (size_t k = 0; k < list.size(); ++k) {
      Epoch& e = list[k];
      const auto now = e.anchor ? T_cw.find(e.anchor->id) : T_cw.end();
      if (now == T_cw.end()) {
        const uint32_t end = k + 1 < list.size() ? list[k + 1].first_id : keyframe_id_space(static_cast<int>(r)).end;
        const auto oldest = T_cw.lower_bound(e.first_id);
        e.anchor.reset();
        if (oldest != T_cw.end() && oldest->first < end) e.anchor = Anchor{oldest->first, oldest->second};
        continue;
      }
      // The anchor's pose in the robot's frame, T_cw * T_group_robot, stays what it was.
      const Eigen::Isometry3d M = now->second.inverse() * e.anchor->T_cw;
      e.T_group_epoch = M * e.T_group_epoch;
      e.anchor->T_cw = now->second;
      // World = robot 0's first map: T_world_group * T_group_epoch of that map stays put.
      if (r == 0 && k == 0 && groups_[e.group].T_world_group)
        groups_[e.group].T_world_group = *groups_[e.group].T_world_group * M.inverse();
    }
  }
}

void RobotFrames::save_to(std::vector<MapEpochRecord>& epochs, std::vector<MapGroupRecord>& groups) const {
  std::lock_guard<std::mutex> lock(mutex_);
  epochs.clear();
  groups.clear();
  for (size_t r = 0; r < epochs_.size(); ++r)
    for (const Epoch& e : epochs_[r])
      epochs.push_back(MapEpochRecord{static_cast<uint32_t>(r), e.first_id, e.group, e.T_group_epoch});
  for (const Group& g : groups_) groups.push_back(MapGroupRecord{g.T_world_group, g.merged_away});
}

bool RobotFrames::restore(const std::vector<MapEpochRecord>& epochs, const std::vector<MapGroupRecord>& groups,
                          std::string* error) {
  const auto refuse = [error](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  std::vector<std::vector<Epoch>> by_robot(robots());
  for (const MapEpochRecord& e : epochs) {
    if (e.robot >= by_robot.size())
      return refuse("a map of robot " + std::to_string(e.robot) + ", this edge serves " + std::to_string(robots()));
    if (e.group < 0 || static_cast<size_t>(e.group) >= groups.size())
      return refuse("a map in group " + std::to_string(e.group) + " of " + std::to_string(groups.size()));
    auto& list = by_robot[e.robot];
    if (!list.empty() && e.first_id <= list.back().first_id) return refuse("robot maps not in id order");
    if (!keyframe_id_space(static_cast<int>(e.robot)).contains(e.first_id))
      return refuse("a map of robot " + std::to_string(e.robot) + " starting at another robot's id");
    list.push_back(Epoch{e.first_id, e.group, e.T_group_epoch});
  }
  for (size_t r = 0; r < by_robot.size(); ++r)
    if (by_robot[r].empty()) return refuse("no map for robot " + std::to_string(r));
  std::vector<Group> restored;
  for (const MapGroupRecord& g : groups) restored.push_back(Group{g.T_world_group, g.merged_away});
  std::lock_guard<std::mutex> lock(mutex_);
  epochs_ = std::move(by_robot);
  groups_ = std::move(restored);
  return true;
}

void transform_record(KeyFrameRecord& r, const Eigen::Isometry3d& T) {
  r.T_wc = T * r.T_wc;
  const Eigen::Isometry3f Tf = T.cast<float>();
  for (NewPointRecord& p : r.new_points) p.position = Tf * p.position;
}

void transform_update(MapUpdateRecord& u, const Eigen::Isometry3d& T) {
  for (KeyFrameRecord& k : u.keyframes) transform_record(k, T);
  const Eigen::Isometry3f Tf = T.cast<float>();
  for (MapPointRecord& p : u.points) {
    p.position = Tf * p.position;
    p.normal = Tf.linear() * p.normal;
  }
}

}  // namespace edge_slam
