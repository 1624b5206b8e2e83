#include "edge_slam/module/local_mapping.h"

#include <chrono>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "edge_slam/module/neighbour_fusion.h"
#include "edge_slam/optimize/local_bundle_adjustment.h"
#include "edge_slam/util/log.h"
#include "edge_slam/util/stopwatch.h"

namespace edge_slam {
namespace {
using Clock = std::chrono::steady_clock;
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
  drain_held_ = drain;
  queue_.close();
  release_all();  // held-back KeyFrames are mapped (drain) or dropped like the queue
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

void LocalMapping::request_stop(const std::vector<int>& maps) {
  std::lock_guard<std::mutex> lock(pause_mutex_);
  if (maps.empty() || !group_of) {
    paused_maps_.insert(kEveryMap);
  } else {
    for (int m : maps) paused_maps_.insert(m);
  }
  // A local BA of a held-back map gives way at once (ORB-SLAM2's abort flag); another map's goes on.
  if (processing_ && held_back_locked(processing_map_)) abort_ba_ = true;
}

bool LocalMapping::held_back_locked(int map) const {
  return paused_maps_.count(kEveryMap) > 0 || paused_maps_.count(map) > 0;
}

bool LocalMapping::stopped() const {
  std::lock_guard<std::mutex> lock(pause_mutex_);
  return !paused_maps_.empty() && !(processing_ && held_back_locked(processing_map_));
}

bool LocalMapping::wait_until_stopped(double timeout_s) const {
  if (!running_) return true;
  std::unique_lock<std::mutex> lock(pause_mutex_);
  return pause_cv_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                            [&] { return finished_ || !(processing_ && held_back_locked(processing_map_)); });
}

void LocalMapping::release(const std::vector<int>& maps) {
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    auto drop = [&](int m) {
      const auto it = paused_maps_.find(m);
      if (it != paused_maps_.end()) paused_maps_.erase(it);
    };
    if (maps.empty() || !group_of) {
      drop(kEveryMap);
    } else {
      for (int m : maps) drop(m);
    }
  }
  pause_cv_.notify_all();
}

void LocalMapping::release_all() {
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    paused_maps_.clear();
  }
  pause_cv_.notify_all();
}

int LocalMapping::map_of(const std::shared_ptr<KeyFrame>& kf) const {
  return group_of && kf ? group_of(kf->id()) : 0;
}

std::shared_ptr<KeyFrame> LocalMapping::next_keyframe() {
  std::unique_lock<std::mutex> lock(pause_mutex_);
  // Held-back KeyFrames are older than any queued one of the same map: they go first.
  for (auto it = held_.begin(); it != held_.end(); ++it) {
    const int map = map_of(*it);
    if (held_back_locked(map)) continue;
    auto kf = *it;
    held_.erase(it);
    processing_ = true;
    processing_map_ = map;
    return kf;
  }
  if (!held_.empty() && queue_.size() == 0) {
    // Only held-back KeyFrames: wait for a release (or a new KeyFrame, checked within 20 ms).
    pause_cv_.wait_for(lock, std::chrono::milliseconds(20));
    return nullptr;
  }
  lock.unlock();
  auto item = queue_.pop_for(std::chrono::milliseconds(20));
  if (!item) return nullptr;
  lock.lock();
  const int map = map_of(*item);
  if (held_back_locked(map)) {
    held_.push_back(*item);
    return nullptr;
  }
  processing_ = true;
  processing_map_ = map;
  return *item;
}

void LocalMapping::run() {
  for (;;) {
    auto kf = next_keyframe();
    bool processing;
    {
      std::lock_guard<std::mutex> lock(pause_mutex_);
      processing = processing_;
    }
    if (!processing) {
      if (queue_.closed() && queue_.size() == 0 && (held_.empty() || !drain_held_)) break;
      if (!busy_ && held_.empty()) set_idle(true);
      continue;
    }
    busy_ = true;
    set_idle(false);
    bool beside_a_pause;
    {
      std::lock_guard<std::mutex> lock(pause_mutex_);
      beside_a_pause = !paused_maps_.empty();
    }
    process_keyframe(kf);
    busy_ = false;
    {
      std::lock_guard<std::mutex> lock(pause_mutex_);
      processing_ = false;
    }
    pause_cv_.notify_all();
    if (beside_a_pause && kf) {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      ++stats_.keyframes_mapped_beside_a_pause;
    }
    ++completed_;
    if (!new_keyframes_waiting() && held_.empty()) set_idle(true);
  }
  {
    std::lock_guard<std::mutex> lock(pause_mutex_);
    finished_ = true;  // a finished mapper counts as stopped for waiters
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
  const Stopwatch t0;
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
    stop_requested = held_back_locked(map_of(kf));
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
    process_ms_.push_back(t0.ms());
  }
  if (on_keyframe_processed && !kf->is_bad()) on_keyframe_processed(kf);
  if (on_keyframe_done) on_keyframe_done(kf);
}

void LocalMapping::run_local_ba(const std::shared_ptr<KeyFrame>& kf) {
  const Stopwatch t0;
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
  local_ba_ms_.push_back(t0.ms());
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
