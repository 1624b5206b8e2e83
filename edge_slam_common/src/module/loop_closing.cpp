#include "edge_slam/module/loop_closing.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <cstdlib>
#include <sstream>

#include "edge_slam/module/full_ba_update.h"
#include "edge_slam/module/local_mapping.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "edge_slam/optimize/full_bundle_adjustment.h"
#include "edge_slam/util/log.h"
#include "edge_slam/util/stopwatch.h"

namespace edge_slam {
namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

LoopClosing::LoopClosing(std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
                         LocalMapping* local_mapping, const LoopClosingParams& params)
    : map_(std::move(map)),
      database_(std::move(database)),
      local_mapping_(local_mapping),
      params_(params),
      detector_(params.detector),
      queue_(params.queue_capacity),
      debug_(std::getenv("EDGE_SLAM_DEBUG_LOOP") != nullptr) {}

LoopClosing::~LoopClosing() { shutdown(false); }

void LoopClosing::start() {
  if (thread_.joinable()) return;
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void LoopClosing::shutdown(bool drain) {
  if (!drain) {
    queue_.clear();
    shutting_down_ = true;
    std::lock_guard<std::mutex> lock(full_ba_mutex_);
    for (auto& job : full_bas_) job.abort = true;
  }
  queue_.close();
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(full_ba_mutex_);
  for (auto& job : full_bas_)
    if (job.thread.joinable()) job.thread.join();
  full_bas_.clear();
}

void LoopClosing::insert_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  ++submitted_;
  if (queue_.push(kf)) {
    ++completed_;
    log_warn("[loop] queue full: oldest keyframe dropped");
  }
}

void LoopClosing::run() {
  while (auto kf = queue_.pop()) {
    busy_ = true;
    process_keyframe(*kf);
    busy_ = false;
    ++completed_;
  }
  running_ = false;
}

bool LoopClosing::wait_until_idle(double timeout_s) const {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while ((completed_.load() < submitted_.load() && running_) || full_bas_running_ > 0) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

void LoopClosing::stop_full_bas(const std::vector<int>& maps) {
  std::lock_guard<std::mutex> lock(full_ba_mutex_);
  for (auto it = full_bas_.begin(); it != full_bas_.end();) {
    const bool of_these = maps.empty() || std::find(maps.begin(), maps.end(), it->map) != maps.end();
    if (!of_these && !it->done) {
      ++it;
      continue;
    }
    if (!it->done) {
      log_info(log_text("[loop] aborting the running full BA of map ", it->map, " (a new loop arrived in it)"));
      it->abort = true;
    }
    if (it->thread.joinable()) it->thread.join();
    it = full_bas_.erase(it);
  }
}

void LoopClosing::save_detector_to(std::vector<LoopGroupRecord>& groups, std::vector<LoopRobotRecord>& robots) const {
  std::lock_guard<std::mutex> lock(detector_mutex_);
  detector_.save_to(groups, robots);
}

void LoopClosing::restore_detector(const std::vector<LoopGroupRecord>& groups,
                                   const std::vector<LoopRobotRecord>& robots) {
  std::lock_guard<std::mutex> lock(detector_mutex_);
  detector_.restore(groups, robots);
}

bool LoopClosing::process_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  const Stopwatch t0;
  if (!kf || kf->is_bad() || !map_->keyframe(kf->id())) return false;
  std::vector<std::shared_ptr<KeyFrame>> candidates;
  {
    std::lock_guard<std::mutex> lock(detector_mutex_);
    candidates = detector_.detect(*map_, *database_, kf);
    if (debug_) {
      log_info(log_text("[loop] KF ", kf->id(), ": min score ", detector_.last_min_score(), ", ",
          detector_.last_raw_candidates(), " raw candidate(s), ", candidates.size(), " consistent"));
    }
  }
  LoopMatch match;
  std::string why;
  const bool found = !candidates.empty() && verify_loop(*map_, kf, candidates, match, &why, params_.verifier);
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    detect_ms_.push_back(t0.ms());
  }
  if (!candidates.empty() && !found)
    log_info(log_text("[loop] KF ", kf->id(), ": ", candidates.size(),
        " consistent candidate(s) failed verification\n", why));
  if (!found) return false;
  if (debug_) {
    // Poses at verification (camera in world, TUM order), to be compared with ground truth offline.
    auto pose = [](const Eigen::Isometry3d& T_wc) {
      const Eigen::Quaterniond q(T_wc.rotation());
      return log_text(T_wc.translation().x(), " ", T_wc.translation().y(), " ", T_wc.translation().z(), " ", q.x(),
                      " ", q.y(), " ", q.z(), " ", q.w());
    };
    log_info(log_text("[loop-debug] ", kf->id(), " ", std::to_string(kf->stamp()), " ", pose(kf->T_wc()), " | ",
        match.loop_kf->id(), " ", std::to_string(match.loop_kf->stamp()), " ", pose(match.loop_kf->T_wc()), " | ",
        pose(match.T_cw_corrected.inverse()), " | ", pose(match.T_cw_aligned.inverse())));
  }

  const Stopwatch t1;
  // Two groups (robots whose maps are not joined yet): a merge. The group with the higher id
  // moves rigidly into the other's coordinates by the verified transform (so group 0, the
  // world, never moves), after which the loop correction is near identity.
  const int current_group = map_of(kf->id());
  const int loop_group = map_of(match.loop_kf->id());
  const bool merge = current_group != loop_group && current_group >= 0 && loop_group >= 0;
  const int from = std::max(current_group, loop_group), into = std::min(current_group, loop_group);
  // Serialised per map: only this map's (both maps' for a merge) full BA and mapping give way.
  const std::vector<int> maps = merge ? std::vector<int>{from, into} : std::vector<int>{current_group};
  stop_full_bas(maps);
  if (local_mapping_) {
    local_mapping_->request_stop(maps);
    if (!local_mapping_->wait_until_stopped(params_.mapper_stop_timeout_s)) {
      local_mapping_->release(maps);
      log_warn(log_text("[loop] local mapping did not pause in time: loop KF ", kf->id(), " <-> KF ",
          match.loop_kf->id(), " dropped"));
      return false;
    }
  }
  Eigen::Isometry3d T_into_from = Eigen::Isometry3d::Identity();
  LoopCorrectionReport report;
  double locked_ms = 0;   // under the map lock, which the other robots' mapping and KeyFrame arrivals wait on
  double longest_ms = 0;  // ... the longest of its holds: what they wait at most
  double move_ms = 0;     // of which moving the merged map into the other's coordinates
  {
    std::unique_lock<std::mutex> lock(map_->update_mutex());
    Stopwatch held;
    const auto hold_ended = [&] {
      const double ms = held.ms();
      locked_ms += ms;
      longest_ms = std::max(longest_ms, ms);
    };
    if (on_map_moved) on_map_moved();
    if (merge) {
      // T_cw_corrected is the current camera seen from the loop side.
      const Eigen::Isometry3d T_loop_current = match.T_cw_corrected.inverse() * kf->T_cw();
      T_into_from = from == current_group ? T_loop_current : T_loop_current.inverse();
      const Stopwatch moving;
      move_group(from, T_into_from);
      move_ms = moving.ms();
      if (from == loop_group) match.T_cw_corrected = kf->T_cw();  // the loop side came to it
      if (on_merge) on_merge(from, into, T_into_from);
    }
    // After a merge every KeyFrame of `from` reports `into`.
    const int corrected_map = merge ? into : current_group;
    std::function<bool(uint32_t)> in_map;
    std::function<void(const std::function<void()>&)> without_lock;
    if (group_of) {
      in_map = [this, corrected_map](uint32_t id) { return group_of(id) == corrected_map; };
      // Several robots: the fusion's search (the longest step, up to ~70 ms on fr1) runs with the
      // lock released, so the other robots' mapping and arrivals go on; the maps corrected stay
      // paused. The map is then moved but not yet fused: each robot's frame follows it already.
      // One robot keeps ORB-SLAM2's single hold (a monolithic tracker waits on the same lock).
      without_lock = [&](const std::function<void()>& work) {
        if (on_map_moved) on_map_moved();
        hold_ended();
        lock.unlock();
        work();
        lock.lock();
        held = Stopwatch();
      };
    }
    report = correct_loop(*map_, kf, match, params_.correction, in_map, without_lock);
    if (on_map_moved) on_map_moved();
    hold_ended();
  }
  if (local_mapping_) local_mapping_->release(maps);
  if (report.group_keyframes == 0 && !merge) {
    log_info(log_text("[loop] KF ", kf->id(), " <-> KF ", match.loop_kf->id(), " not corrected: ", report.message));
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(detector_mutex_);
    detector_.set_last_loop_keyframe(kf->id(), group_of);  // after a merge: both robots' map
  }
  log_info(log_text("[loop] ", (merge ? "maps merged" : "loop closed"), ": KF ", kf->id(), " <-> KF ",
      match.loop_kf->id(), ", ", match.num_matches, " matches (", report.group_keyframes, " KFs corrected, ",
      report.fused_points, " points fused, ", report.new_loop_links, " new links, ", report.message, ", cost ",
      report.graph_initial_cost, " -> ", report.graph_final_cost, "; current KF moved ", report.current_shift_m * 100, " cm ",
      report.current_shift_deg, " deg; ", report.group_on_loop_side, " of its group on the loop side; map locked ",
      locked_ms, " ms, at most ", longest_ms, " at a time: move ", move_ms, ", group ", report.group_ms, ", fusion ",
      report.fuse_ms, " (+ search ", report.fuse_search_ms, (group_of ? " unlocked" : ""), "), links ",
      report.links_ms, ", graph ", report.graph_ms, ", points follow ", report.follow_ms, ")"));
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    if (merge)
      merges_.push_back(MergeEvent{kf->id(), match.loop_kf->id(), from, into, match.num_matches, T_into_from, report});
    else
      loops_.push_back(LoopEvent{kf->id(), match.loop_kf->id(), match.num_matches, report});
    correct_ms_.push_back(t1.ms());
    correct_locked_ms_.push_back(locked_ms);
    correct_longest_lock_ms_.push_back(longest_ms);
  }
  start_full_ba(kf->id(), merge ? into : current_group);
  return true;
}

void LoopClosing::start_full_ba(uint32_t kf_id, int map) {
  if (!params_.full_ba) return;
  std::lock_guard<std::mutex> lock(full_ba_mutex_);
  FullBa& job = full_bas_.emplace_back();
  job.map = map;
  job.loop_kf_id = kf_id;
  ++full_bas_running_;
  if (params_.full_ba_in_background)
    job.thread = std::thread([this, &job] { run_full_ba(job); });
  else
    run_full_ba(job);
}

void LoopClosing::move_group(int from, const Eigen::Isometry3d& T_into_from) {
  const uint64_t pass = ++merge_passes_ + (uint64_t{1} << 40);  // distinct from any update's pass
  int moved_kfs = 0, moved_points = 0;
  for (const auto& k : map_->keyframes()) {
    if (group_of(k->id()) != from) continue;
    k->set_pose(k->T_cw() * T_into_from.inverse());
    ++moved_kfs;
    for (uint32_t id : k->map_point_ids())
      if (id != kNoId)
        if (auto mp = map_->map_point(id); mp && mp->transform_once(T_into_from, pass)) ++moved_points;
  }
  log_info(log_text("[loop] merging map ", from, ": ", moved_kfs, " KFs and ", moved_points, " points moved"));
}

void LoopClosing::run_full_ba(FullBa& job) {
  const Stopwatch t0;
  const uint32_t loop_kf_id = job.loop_kf_id;
  const std::vector<int> maps{job.map};
  // The other robots' maps (not joined to this one) are not in the problem and do not move.
  std::function<bool(uint32_t)> in_map;
  if (group_of) in_map = [this, &job](uint32_t id) { return group_of(id) == job.map; };
  BundleAdjustmentProblem problem;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    problem = build_full_ba_problem(*map_, in_map);
  }
  const auto finish = [&] {
    job.done = true;
    --full_bas_running_;
  };
  const BundleAdjustmentResult result =
      problem.keyframes.size() < 2 ? BundleAdjustmentResult{}
                                   : run_full_bundle_adjustment(problem, params_.full_ba_iterations, &job.abort);
  if (!result.ok || result.aborted || job.abort || shutting_down_) {
    log_warn(log_text("[loop] full BA after loop at KF ", loop_kf_id, " ",
        (result.ok ? "aborted" : "failed: " + result.message), "; map left as corrected"));
    finish();
    return;
  }
  bool paused = true;
  if (local_mapping_) {
    local_mapping_->request_stop(maps);
    paused = local_mapping_->wait_until_stopped(params_.mapper_stop_timeout_s);
  }
  int propagated = 0;
  if (paused) {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    if (on_map_moved) on_map_moved();
    propagated = apply_full_ba_result(*map_, result);
    if (on_map_moved) on_map_moved();
  }
  if (local_mapping_) local_mapping_->release(maps);
  const double ms = t0.ms();
  log_info(log_text("[loop] full BA after loop at KF ", loop_kf_id, (paused ? " applied: " : " NOT applied: "),
      problem.keyframes.size(), " KFs, ", problem.points.size(), " points, ", propagated, " newer KFs propagated, ",
      static_cast<int>(ms), " ms"));
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++full_ba_runs_;
    full_ba_ms_.push_back(ms);
  }
  finish();
}

int LoopClosing::loops_closed() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return static_cast<int>(loops_.size());
}
std::vector<MergeEvent> LoopClosing::merges() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return merges_;
}
std::vector<LoopEvent> LoopClosing::loops() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return loops_;
}
int LoopClosing::full_ba_runs() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return full_ba_runs_;
}
std::vector<double> LoopClosing::detection_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return detect_ms_;
}
std::vector<double> LoopClosing::correction_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return correct_ms_;
}
std::vector<double> LoopClosing::correction_locked_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return correct_locked_ms_;
}
std::vector<double> LoopClosing::correction_longest_lock_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return correct_longest_lock_ms_;
}
std::vector<double> LoopClosing::full_ba_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return full_ba_ms_;
}

}  // namespace edge_slam
