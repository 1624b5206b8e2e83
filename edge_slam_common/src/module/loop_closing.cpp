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

namespace edge_slam {
namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
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
    abort_full_ba_ = true;
  }
  queue_.close();
  if (thread_.joinable()) thread_.join();
  if (full_ba_thread_.joinable()) full_ba_thread_.join();
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
  while ((completed_.load() < submitted_.load() && running_) || full_ba_running_) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

void LoopClosing::stop_full_ba() {
  if (!full_ba_thread_.joinable()) return;
  if (full_ba_running_) log_info("[loop] aborting the running full BA (a new loop arrived)");
  abort_full_ba_ = true;
  full_ba_thread_.join();
  abort_full_ba_ = false;
}

bool LoopClosing::process_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  const auto t0 = Clock::now();
  if (!kf || kf->is_bad() || !map_->keyframe(kf->id())) return false;
  const auto candidates = detector_.detect(*map_, *database_, kf);
  if (debug_) {
    log_info(log_text("[loop] KF ", kf->id(), ": min score ", detector_.last_min_score(), ", ",
        detector_.last_raw_candidates(), " raw candidate(s), ", candidates.size(), " consistent"));
  }
  LoopMatch match;
  std::string why;
  const bool found = !candidates.empty() && verify_loop(*map_, kf, candidates, match, &why, params_.verifier);
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    detect_ms_.push_back(ms_since(t0));
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

  const auto t1 = Clock::now();
  stop_full_ba();
  if (local_mapping_) {
    local_mapping_->request_stop();
    if (!local_mapping_->wait_until_stopped(params_.mapper_stop_timeout_s)) {
      local_mapping_->release();
      log_warn(log_text("[loop] local mapping did not pause in time: loop KF ", kf->id(), " <-> KF ",
          match.loop_kf->id(), " dropped"));
      return false;
    }
  }
  // Two groups (robots whose maps are not joined yet): a merge. The group with the higher id
  // moves rigidly into the other's coordinates by the verified transform (so group 0, the
  // world, never moves), after which the loop correction is near identity.
  const int current_group = group_of ? group_of(kf->id()) : 0;
  const int loop_group = group_of ? group_of(match.loop_kf->id()) : 0;
  const bool merge = current_group != loop_group && current_group >= 0 && loop_group >= 0;
  const int from = std::max(current_group, loop_group), into = std::min(current_group, loop_group);
  Eigen::Isometry3d T_into_from = Eigen::Isometry3d::Identity();
  LoopCorrectionReport report;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    if (on_map_moved) on_map_moved();
    if (merge) {
      // T_cw_corrected is the current camera seen from the loop side.
      const Eigen::Isometry3d T_loop_current = match.T_cw_corrected.inverse() * kf->T_cw();
      T_into_from = from == current_group ? T_loop_current : T_loop_current.inverse();
      move_group(from, T_into_from);
      if (from == loop_group) match.T_cw_corrected = kf->T_cw();  // the loop side came to it
      if (on_merge) on_merge(from, into, T_into_from);
    }
    report = correct_loop(*map_, kf, match, params_.correction);
    if (on_map_moved) on_map_moved();
  }
  if (local_mapping_) local_mapping_->release();
  if (report.group_keyframes == 0 && !merge) {
    log_info(log_text("[loop] KF ", kf->id(), " <-> KF ", match.loop_kf->id(), " not corrected: ", report.message));
    return false;
  }
  detector_.set_last_loop_keyframe(kf->id());
  log_info(log_text("[loop] ", (merge ? "maps merged" : "loop closed"), ": KF ", kf->id(), " <-> KF ",
      match.loop_kf->id(), ", ", match.num_matches, " matches (", report.group_keyframes, " KFs corrected, ",
      report.fused_points, " points fused, ", report.new_loop_links, " new links, ", report.message, ", cost ",
      report.graph_initial_cost, " -> ", report.graph_final_cost, "; current KF moved ", report.current_shift_m * 100, " cm ",
      report.current_shift_deg, " deg; ", report.group_on_loop_side, " of its group on the loop side)"));
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    if (merge)
      merges_.push_back(MergeEvent{kf->id(), match.loop_kf->id(), from, into, match.num_matches, T_into_from, report});
    else
      loops_.push_back(LoopEvent{kf->id(), match.loop_kf->id(), match.num_matches, report});
    correct_ms_.push_back(ms_since(t1));
  }
  start_full_ba(kf->id());
  return true;
}

void LoopClosing::start_full_ba(uint32_t kf_id) {
  if (!params_.full_ba) return;
  full_ba_running_ = true;
  if (params_.full_ba_in_background)
    full_ba_thread_ = std::thread([this, kf_id] { run_full_ba(kf_id); });
  else
    run_full_ba(kf_id);
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

void LoopClosing::run_full_ba(uint32_t loop_kf_id) {
  const auto t0 = Clock::now();
  BundleAdjustmentProblem problem;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    problem = build_full_ba_problem(*map_);
  }
  // Maps not joined yet (several robots) each keep their gauge: the first KeyFrame of each group is held.
  if (group_of) {
    std::map<int, size_t> first_of_group;
    for (size_t i = 0; i < problem.keyframes.size(); ++i) {
      const int g = group_of(problem.keyframes[i].id);
      auto it = first_of_group.find(g);
      if (it == first_of_group.end() || problem.keyframes[i].id < problem.keyframes[it->second].id) first_of_group[g] = i;
    }
    if (first_of_group.size() > 1)
      for (const auto& [g, i] : first_of_group) problem.keyframes[i].fixed = true;
  }
  const BundleAdjustmentResult result =
      problem.keyframes.size() < 2 ? BundleAdjustmentResult{}
                                   : run_full_bundle_adjustment(problem, params_.full_ba_iterations, &abort_full_ba_);
  if (!result.ok || result.aborted || abort_full_ba_) {
    log_warn(log_text("[loop] full BA after loop at KF ", loop_kf_id, " ",
        (result.ok ? "aborted" : "failed: " + result.message), "; map left as corrected"));
    full_ba_running_ = false;
    return;
  }
  bool paused = true;
  if (local_mapping_) {
    local_mapping_->request_stop();
    paused = local_mapping_->wait_until_stopped(params_.mapper_stop_timeout_s);
  }
  int propagated = 0;
  if (paused) {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    if (on_map_moved) on_map_moved();
    propagated = apply_full_ba_result(*map_, result);
    if (on_map_moved) on_map_moved();
  }
  if (local_mapping_) local_mapping_->release();
  const double ms = ms_since(t0);
  log_info(log_text("[loop] full BA after loop at KF ", loop_kf_id, (paused ? " applied: " : " NOT applied: "),
      problem.keyframes.size(), " KFs, ", problem.points.size(), " points, ", propagated, " newer KFs propagated, ",
      static_cast<int>(ms), " ms"));
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++full_ba_runs_;
    full_ba_ms_.push_back(ms);
  }
  full_ba_running_ = false;
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
std::vector<double> LoopClosing::full_ba_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return full_ba_ms_;
}

}  // namespace edge_slam
