#include "edge_slam/module/local_mapping.h"

#include <chrono>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "edge_slam/module/neighbour_fusion.h"
#include "edge_slam/optimize/local_bundle_adjustment.h"
#include "edge_slam/util/log.h"

namespace edge_slam {
namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
}  // namespace

LocalMapping::LocalMapping(std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
                           std::shared_ptr<const BowVocabulary> vocabulary, const LocalMappingParams& params)
    : map_(std::move(map)),
      database_(std::move(database)),
      vocabulary_(std::move(vocabulary)),
      params_(params),
      queue_(params.queue_capacity),
      recent_(params.point_culling) {}

LocalMapping::~LocalMapping() { shutdown(false); }

void LocalMapping::start() {
  if (running_) return;
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void LocalMapping::shutdown(bool drain) {
  if (!drain) queue_.clear();
  queue_.close();
  release();
  if (thread_.joinable()) thread_.join();
  running_ = false;
}

void LocalMapping::insert_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  set_idle(false);
  abort_ba_ = true;
  ++submitted_;
  if (auto evicted = queue_.push(kf)) {
    if (on_keyframe_done) on_keyframe_done(*evicted);
    ++completed_;
    log_warn("[mapping] queue full: oldest keyframe dropped");
  }
}

void LocalMapping::set_idle(bool idle) {
  if (idle_.exchange(idle) != idle && on_idle_changed) on_idle_changed(idle);
}

bool LocalMapping::wait_until_idle(double timeout_s) const {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (completed_.load() < submitted_.load() && running_) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

void LocalMapping::request_stop() {
  std::lock_guard<std::mutex> lock(pause_mutex_);
  stop_requested_ = true;
  abort_ba_ = true;
}

bool LocalMapping::wait_until_stopped(double timeout_s) const {
  if (!running_) return true;
  std::unique_lock<std::mutex> lock(pause_mutex_);
  return pause_cv_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return stopped_.load(); });
}

void LocalMapping::release() {
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    stop_requested_ = false;
  }
  pause_cv_.notify_all();
}

void LocalMapping::pause_if_requested() {
  std::unique_lock<std::mutex> lock(pause_mutex_);
  if (!stop_requested_) return;
  stopped_ = true;
  pause_cv_.notify_all();
  pause_cv_.wait(lock, [&] { return !stop_requested_; });
  stopped_ = false;
}

void LocalMapping::run() {
  for (;;) {
    pause_if_requested();
    auto item = queue_.pop_for(std::chrono::milliseconds(20));
    if (!item) {
      if (queue_.closed() && queue_.size() == 0) break;
      if (!busy_) set_idle(true);
      continue;
    }
    busy_ = true;
    set_idle(false);
    process_keyframe(*item);
    busy_ = false;
    ++completed_;
    if (!new_keyframes_waiting()) set_idle(true);
  }
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    stopped_ = true;  // a finished mapper counts as stopped for waiters
  }
  pause_cv_.notify_all();
  set_idle(true);
}

void LocalMapping::finish_insertion(const std::shared_ptr<KeyFrame>& kf) {
  if (!kf->has_bow() && vocabulary_ && !vocabulary_->empty()) kf->compute_bow(*vocabulary_);
  const auto ids = kf->map_point_ids();
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] == kNoId) continue;
    const auto mp = map_->map_point(ids[i]);
    if (!mp || mp->is_bad()) {
      kf->erase_map_point_id(i);
      continue;
    }
    if (mp->index_in(kf->id()) < 0) {
      // A point this keyframe's record brought (the edge installs a mobile's new points
      // without observations): as new as one tracking made here, so it goes on probation too.
      // Without this no mobile-made point was ever culled on the edge.
      const bool made_here = mp->reference_kf_id() == kf->id() && mp->num_observations() == 0;
      mp->add_observation(kf->id(), static_cast<int>(i));
      mp->update_normal_and_depth(*map_);
      mp->update_descriptor(*map_);
      if (made_here) recent_.add(mp->id(), kf->id());
    } else if (mp->reference_kf_id() == kf->id() && mp->num_observations() == 1) {
      recent_.add(mp->id(), kf->id());  // made by tracking from this keyframe's depth
    }
  }
  kf->update_connections(*map_);
  if (kf->has_bow() && database_) database_->add(kf);
}

void LocalMapping::refute_points(const std::vector<uint32_t>& ids) {
  if (ids.empty()) return;
  std::lock_guard<std::mutex> lock(refuted_mutex_);
  refuted_.insert(ids.begin(), ids.end());
}

void LocalMapping::process_keyframe(const std::shared_ptr<KeyFrame>& kf) {
  const auto t0 = Clock::now();
  if (!kf || kf->is_bad() || !map_->keyframe(kf->id())) {
    log_info(log_text("[mapping] keyframe ", (kf ? std::to_string(kf->id()) : "null"),
        " was erased while queued: skipped"));
    {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++stats_.keyframes_skipped;
    }
    if (on_keyframe_done && kf) on_keyframe_done(kf);
    return;
  }
  int culled = 0, refuted_culled = 0, created = 0, fused = 0, kf_culled = 0;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    finish_insertion(kf);
    std::unordered_set<uint32_t> refuted;
    {
      std::lock_guard<std::mutex> refuted_lock(refuted_mutex_);
      refuted.swap(refuted_);
    }
    culled = recent_.cull(*map_, kf->id(), &refuted, &refuted_culled);
    const auto points = triangulate_new_points(*map_, kf, params_.triangulation,
                                               [this] { return new_keyframes_waiting(); });
    for (const auto& mp : points) recent_.add(mp->id(), kf->id());
    created = static_cast<int>(points.size());
  }
  if (!new_keyframes_waiting()) {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    fused = fuse_with_neighbours(*map_, kf);
  }
  bool stop_requested;
  std::vector<std::shared_ptr<KeyFrame>> culled_kfs;
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    stop_requested = stop_requested_;
  }
  if (!new_keyframes_waiting() && !stop_requested) {
    if (params_.local_ba && map_->num_keyframes() > 2) run_local_ba(kf);
    if (params_.cull_keyframes) {
      std::lock_guard<std::mutex> lock(map_->update_mutex());
      kf_culled = cull_redundant_keyframes(*map_, database_.get(), *kf, params_.keyframe_culling, &culled_kfs);
    }
  }
  if (on_keyframes_culled && !culled_kfs.empty()) on_keyframes_culled(culled_kfs);
  {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    ++stats_.keyframes_processed;
    stats_.points_culled += culled;
    stats_.points_refuted += refuted_culled;
    stats_.points_created += created;
    stats_.points_fused += fused;
    stats_.keyframes_culled += kf_culled;
    process_ms_.push_back(ms_since(t0));
  }
  if (on_keyframe_processed && !kf->is_bad()) on_keyframe_processed(kf);
  if (on_keyframe_done) on_keyframe_done(kf);
}

void LocalMapping::run_local_ba(const std::shared_ptr<KeyFrame>& kf) {
  const auto t0 = Clock::now();
  abort_ba_ = false;
  BundleAdjustmentProblem problem;
  {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    problem = build_local_ba_problem(*map_, *kf, params_.ba_window);
  }
  if (problem.keyframes.empty()) return;
  LocalBaOptions options;
  options.first_pass_iterations = params_.ba_first_pass_iterations;
  options.second_pass_iterations = params_.ba_second_pass_iterations;
  options.num_threads = params_.ba_num_threads;
  options.abort = &abort_ba_;
  const BundleAdjustmentResult result = run_local_bundle_adjustment(problem, options);
  if (result.ok) {
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    apply_ba_result(*map_, problem, result, true);
  }
  std::lock_guard<std::mutex> lock(stats_mutex_);
  ++stats_.local_ba_runs;
  for (const BaKeyFrame& b : problem.keyframes) ++(b.fixed ? stats_.local_ba_fixed_keyframes : stats_.local_ba_free_keyframes);
  stats_.local_ba_observations += static_cast<long long>(problem.observations.size());
  if (result.aborted) ++stats_.local_ba_aborted;
  if (!result.ok) {
    ++stats_.local_ba_failed;
    log_warn(log_text("[mapping] local BA on keyframe ", kf->id(), " failed: ", result.message));
  }
  local_ba_ms_.push_back(ms_since(t0));
}

LocalMappingStats LocalMapping::stats() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return stats_;
}
std::vector<double> LocalMapping::process_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return process_ms_;
}
std::vector<double> LocalMapping::local_ba_times_ms() const {
  std::lock_guard<std::mutex> lock(stats_mutex_);
  return local_ba_ms_;
}

}  // namespace edge_slam
