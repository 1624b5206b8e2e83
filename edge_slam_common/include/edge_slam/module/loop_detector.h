// Loop candidate detection with temporal consistency (ORB-SLAM2's DetectLoop): BoW candidates
// scoring at least the lowest score between the keyframe and its covisibles; a candidate's
// covisible group must overlap the groups of the previous detections `consistency` times in
// a row before it is handed on for geometric verification.
#pragma once
#include <functional>
#include <memory>
#include <map>
#include <set>
#include <vector>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"
#include "edge_slam/io/map_file.h"

namespace edge_slam {

struct LoopDetectorParams {
  uint32_t min_keyframes_after_loop = 10;  // no detection right after a loop (ORB-SLAM2: 10)
  size_t min_map_keyframes = 10;           // nor in a tiny map
  int consistency = 3;                     // ORB-SLAM2: 3
};

class LoopDetector {
 public:
  explicit LoopDetector(const LoopDetectorParams& params = {}) : params_(params) {}
  // Consistent candidates for `kf` (empty most of the time). Updates the group history.
  std::vector<std::shared_ptr<KeyFrame>> detect(const Map& map, const KeyFrameDatabase& database,
                                                const std::shared_ptr<KeyFrame>& kf);
  // No loop detection for the next min_keyframes_after_loop KeyFrames of each robot working in
  // the loop's map: the robot of kf_id, and every other robot whose newest KeyFrame is in that
  // map by map_of (unset: every robot; one robot: one map).
  void set_last_loop_keyframe(uint32_t kf_id, const std::function<int(uint32_t kf_id)>& map_of = {});
  // The detection history for the edge's map file: each robot's run of consistent candidate
  // groups and its pause after the last loop. restore() replaces the history with a saved one, so
  // a restored edge closes the loop it was about to close, and not one right after the last.
  void save_to(std::vector<LoopGroupRecord>& groups, std::vector<LoopRobotRecord>& robots) const;
  void restore(const std::vector<LoopGroupRecord>& groups, const std::vector<LoopRobotRecord>& robots);
  double last_min_score() const { return last_min_score_; }
  size_t last_raw_candidates() const { return last_raw_candidates_; }

 private:
  struct Group {
    std::set<uint32_t> members;
    int consistency = 0;
  };
  LoopDetectorParams params_;
  std::map<int, std::vector<Group>> groups_;  // per robot (util/robot_ids.h)
  std::map<int, uint32_t> last_loop_kf_ids_;  // robot (util/robot_ids.h) -> its newest KeyFrame at the last loop
  std::map<int, uint32_t> newest_kf_ids_;     // robot -> its newest KeyFrame seen by detect()
  double last_min_score_ = 0;
  size_t last_raw_candidates_ = 0;
};

}  // namespace edge_slam
