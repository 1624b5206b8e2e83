#include "edge_slam/module/slam_system.h"

#include <chrono>

#include "edge_slam/module/full_ba_update.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "edge_slam/optimize/full_bundle_adjustment.h"
#include "edge_slam/util/log.h"

namespace edge_slam {

SlamSystem::SlamSystem(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& tracking_params,
                       std::shared_ptr<const BowVocabulary> vocabulary, const SlamSystemOptions& options,
                       RgbEncoding encoding)
    : map_(std::make_shared<Map>()), database_(std::make_shared<KeyFrameDatabase>()) {
  TrackingParams params = for_host(tracking_params, TrackerHost::kMonolithic);
  if (!options.local_mapping) params.depth_counts_twice = false;
  tracking_ = std::make_unique<Tracking>(camera, orb, params, map_, database_, vocabulary, encoding);
  final_full_ba_iterations_ = options.local_mapping ? options.final_full_ba_iterations : 0;
  if (options.local_mapping) {
    threads_ = std::make_unique<MappingThreads>(map_, database_, vocabulary, options.mapping, options.loop,
                                                options.loop_closing && vocabulary);
    simulated_mapping_frames_ = options.simulated_mapping_frames;
    if (simulated_mapping_frames_ <= 0)
      threads_->mapping().on_idle_changed = [this](bool idle) { tracking_->set_mapper_idle(idle); };
  }
  tracking_->set_mapper_idle(true);
  tracking_->on_new_keyframe = [this](const std::shared_ptr<KeyFrame>& kf) {
    {
      std::lock_guard<std::mutex> lock(records_mutex_);
      all_keyframes_[kf->id()] = kf;
    }
    if (threads_) threads_->mapping().insert_keyframe(kf);
  };
  if (threads_) threads_->start();
}

SlamSystem::~SlamSystem() {
  if (threads_) threads_->stop(false);
}

TrackingResult SlamSystem::track_rgbd(const cv::Mat& color, const cv::Mat& depth, double stamp) {
  simulate_mapper_state();
  return record(tracking_->track_rgbd(color, depth, stamp), stamp);
}

TrackingResult SlamSystem::track_frame(Frame frame) {
  const double stamp = frame.stamp;
  simulate_mapper_state();
  return record(tracking_->track_frame(std::move(frame)), stamp);
}

void SlamSystem::simulate_mapper_state() {
  if (simulated_mapping_frames_ > 0 && threads_)
    tracking_->set_mapper_idle(frames_since_keyframe_ >= simulated_mapping_frames_);
}

TrackingResult SlamSystem::record(const TrackingResult& r, double stamp) {
  frames_since_keyframe_ = r.new_keyframe ? 1 : frames_since_keyframe_ + 1;
  if (!r.pose_valid) return r;
  const auto& ref = tracking_->last_frame().reference_kf;
  if (!ref) return r;
  // Under the map lock, so that no BA moves the reference keyframe while we read it.
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  std::lock_guard<std::mutex> lock(records_mutex_);
  all_keyframes_.emplace(ref->id(), ref);  // a reference from the initial map, or an update
  frames_.push_back(FrameAnchor{stamp, ref->id(), ref->T_cw() * r.T_cw.inverse()});
  return r;
}

bool SlamSystem::wait_until_idle(double timeout_s) const {
  return threads_ ? threads_->wait_until_idle(timeout_s, 2) : true;
}

bool SlamSystem::finish(double timeout_s) {
  if (finished_) return true;
  finished_ = true;
  // Mapping feeds loop closing and a full BA pauses mapping: wait until both are quiet.
  const bool ok = threads_ ? threads_->wait_until_idle(timeout_s, 3) : true;
  if (threads_) threads_->stop(ok);
  if (ok && final_full_ba_iterations_ > 0) {
    // The threads are stopped: the map is ours, but the lock keeps readers (trajectory()) out.
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    const BundleAdjustmentProblem problem = build_full_ba_problem(*map_);
    if (problem.keyframes.size() >= 2) {
      const BundleAdjustmentResult result = run_full_bundle_adjustment(problem, final_full_ba_iterations_);
      if (result.ok) apply_full_ba_result(*map_, result);
      else log_error(log_text("[slam] final full BA failed: ", result.message, "; map kept as it was"));
    }
  }
  return ok;
}

std::vector<std::pair<double, Eigen::Isometry3d>> SlamSystem::trajectory() const {
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  std::lock_guard<std::mutex> lock(records_mutex_);
  TrajectoryComposer composer;
  for (const auto& [id, kf] : all_keyframes_) {
    if (!kf->is_bad()) composer.set_keyframe_pose(id, kf->T_wc());
    else composer.set_parent_link(KeyFrameLink{id, kf->parent_id(), kf->T_cp().inverse()});  // culled: on its parent then
  }
  return composer.compose(frames_).poses;
}

}  // namespace edge_slam
