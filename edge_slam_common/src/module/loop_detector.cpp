#include "edge_slam/module/loop_detector.h"

#include <algorithm>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/util/robot_ids.h"

namespace edge_slam {

std::vector<std::shared_ptr<KeyFrame>> LoopDetector::detect(const Map& map, const KeyFrameDatabase& database,
                                                            const std::shared_ptr<KeyFrame>& kf) {
  last_raw_candidates_ = 0;
  if (!kf->has_bow() || kf->is_bad()) return {};
  if (map.num_keyframes() < params_.min_map_keyframes) return {};
  {
    uint32_t& newest = newest_kf_ids_[robot_of_keyframe(kf->id())];
    newest = std::max(newest, kf->id());
  }
  const auto last_loop = last_loop_kf_ids_.find(robot_of_keyframe(kf->id()));
  if (last_loop != last_loop_kf_ids_.end() && kf->id() < last_loop->second + params_.min_keyframes_after_loop)
    return {};

  // The loop must look at least as similar as the keyframe's own neighbours do.
  double min_score = 1.0;
  for (uint32_t id : kf->ordered_neighbours()) {
    const auto nb = map.keyframe(id);
    if (!nb || nb->is_bad() || !nb->has_bow()) continue;
    min_score = std::min(min_score, BowVocabulary::score(kf->bow(), nb->bow()));
  }
  last_min_score_ = min_score;
  // Only keyframes older than this one: tracking indexes keyframes before local mapping has
  // linked them, so a newer one may look unconnected without being a loop. Another robot's
  // KeyFrames are never this one's neighbours-to-be: all of them are candidates (a merge).
  const int robot = robot_of_keyframe(kf->id());
  auto candidates = database.detect_loop_candidates(kf, min_score, map);
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const std::shared_ptr<KeyFrame>& c) {
                                    return robot_of_keyframe(c->id()) == robot && c->id() >= kf->id();
                                  }),
                   candidates.end());
  last_raw_candidates_ = candidates.size();
  // Consistency is counted along one robot's own KeyFrames: another robot's, processed in
  // between, neither extend nor break its run of detections.
  std::vector<Group>& groups = groups_[robot];
  if (candidates.empty()) {
    groups.clear();
    return {};
  }

  std::vector<std::shared_ptr<KeyFrame>> consistent;
  std::vector<Group> current;
  std::vector<bool> extended(groups.size(), false);
  for (const auto& cand : candidates) {
    Group g;
    g.members.insert(cand->id());
    for (uint32_t id : cand->ordered_neighbours()) g.members.insert(id);
    bool enough = false, overlaps_any = false;
    for (size_t k = 0; k < groups.size(); ++k) {
      const bool overlap = std::any_of(g.members.begin(), g.members.end(),
                                       [&](uint32_t id) { return groups[k].members.count(id) > 0; });
      if (!overlap) continue;
      overlaps_any = true;
      const int c = groups[k].consistency + 1;
      if (!extended[k]) {
        current.push_back(Group{g.members, c});
        extended[k] = true;
      }
      if (c >= params_.consistency && !enough) {
        consistent.push_back(cand);
        enough = true;
      }
    }
    if (!overlaps_any) current.push_back(Group{g.members, 0});
  }
  groups = std::move(current);
  return consistent;
}

// Every robot working in the loop's map waits for min_keyframes_after_loop KeyFrames of its own
// after the loop, whoever closed it: that map's loops then come no faster than with one robot
// (its full BA gets the time to finish instead of being aborted by the next robot's loop a
// KeyFrame later). A robot in another map is not held: a loop there neither aborts this map's
// full BA nor is aborted by it (module/loop_closing.h), and its own merge may be due (fr1 in
// three parts: a merge of robots 2 and 3 held robot 1 over the last KeyFrames of its part, the
// ones that would have merged it).
void LoopDetector::set_last_loop_keyframe(uint32_t kf_id, const std::function<int(uint32_t kf_id)>& map_of) {
  const int loop_map = map_of ? map_of(kf_id) : 0;
  for (const auto& [robot, newest] : newest_kf_ids_)
    if (!map_of || map_of(newest) == loop_map) last_loop_kf_ids_[robot] = newest;
  last_loop_kf_ids_[robot_of_keyframe(kf_id)] = kf_id;
}

void LoopDetector::save_to(std::vector<LoopGroupRecord>& groups, std::vector<LoopRobotRecord>& robots) const {
  groups.clear();
  robots.clear();
  for (const auto& [robot, list] : groups_)
    for (const Group& g : list)
      groups.push_back(LoopGroupRecord{static_cast<uint32_t>(robot), g.consistency, {g.members.begin(), g.members.end()}});
  std::map<int, LoopRobotRecord> by_robot;
  for (const auto& [robot, newest] : newest_kf_ids_) by_robot[robot].newest_keyframe = newest;
  for (const auto& [robot, last] : last_loop_kf_ids_) by_robot[robot].last_loop_keyframe = last;
  for (auto& [robot, r] : by_robot) {
    r.robot = static_cast<uint32_t>(robot);
    robots.push_back(r);
  }
}

void LoopDetector::restore(const std::vector<LoopGroupRecord>& groups, const std::vector<LoopRobotRecord>& robots) {
  groups_.clear();
  newest_kf_ids_.clear();
  last_loop_kf_ids_.clear();
  for (const LoopGroupRecord& g : groups)
    groups_[static_cast<int>(g.robot)].push_back(Group{{g.members.begin(), g.members.end()}, g.consistency});
  for (const LoopRobotRecord& r : robots) {
    if (r.newest_keyframe) newest_kf_ids_[static_cast<int>(r.robot)] = *r.newest_keyframe;
    if (r.last_loop_keyframe) last_loop_kf_ids_[static_cast<int>(r.robot)] = *r.last_loop_keyframe;
  }
}

}  // namespace edge_slam
