#include "edge_slam/module/loop_closing.h"

#include <chrono>
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
  LoopCorrectionReport report;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    report = correct_loop(*map_, kf, match, params_.correction);
  }
  if (local_mapping_) local_mapping_->release();
  if (report.group_keyframes == 0) {
    log_info(log_text("[loop] KF ", kf->id(), " <-> KF ", match.loop_kf->id(), " not corrected: ", report.message));
    return false;
  }
  detector_.set_last_loop_keyframe(kf->id());
  log_info(log_text("[loop] loop closed: KF ", kf->id(), " <-> KF ", match.loop_kf->id(), ", ", match.num_matches,
      " matches (", report.group_keyframes, " KFs corrected, ", report.fused_points, " points fused, ",
      report.new_loop_links, " new links, ", report.message, ", cost ", report.graph_initial_cost, " -> ",
      report.graph_final_cost, ")"));
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    loops_.push_back(LoopEvent{kf->id(), match.loop_kf->id(), match.num_matches, report});
    correct_ms_.push_back(ms_since(t1));
  }
  if (params_.full_ba) {
    full_ba_running_ = true;
    if (params_.full_ba_in_background)
      full_ba_thread_ = std::thread([this, id = kf->id()] { run_full_ba(id); });
    else
      run_full_ba(kf->id());
  }
  return true;
}

void LoopClosing::run_full_ba(uint32_t loop_kf_id) {
  const auto t0 = Clock::now();
  BundleAdjustmentProblem problem;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    problem = build_full_ba_problem(*map_);
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
    propagated = apply_full_ba_result(*map_, result);
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
