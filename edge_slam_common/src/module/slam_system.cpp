#include "edge_slam/module/slam_system.h"

#include <chrono>
#include <iostream>

#include "edge_slam/module/full_ba_update.h"
#include "edge_slam/module/map_ba_bridge.h"
#include "edge_slam/optimize/full_bundle_adjustment.h"

namespace edge_slam {

SlamSystem::SlamSystem(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& tracking_params,
                       std::shared_ptr<const BowVocabulary> vocabulary, const SlamSystemOptions& options,
                       RgbEncoding encoding)
    : map_(std::make_shared<Map>()), database_(std::make_shared<KeyFrameDatabase>()) {
  TrackingParams params = tracking_params;
  if (!options.local_mapping) params.depth_counts_twice = false;
  tracking_ = std::make_unique<Tracking>(camera, orb, params, map_, database_, vocabulary, encoding);
  final_full_ba_iterations_ = options.local_mapping ? options.final_full_ba_iterations : 0;
  if (options.local_mapping) {
    mapping_ = std::make_unique<LocalMapping>(map_, database_, vocabulary, options.mapping);
    if (options.loop_closing && vocabulary) {
      loop_ = std::make_unique<LoopClosing>(map_, database_, mapping_.get(), options.loop);
      mapping_->on_keyframe_processed = [this](const std::shared_ptr<KeyFrame>& kf) { loop_->insert_keyframe(kf); };
    }
    simulated_mapping_frames_ = options.simulated_mapping_frames;
    if (simulated_mapping_frames_ <= 0)
      mapping_->on_idle_changed = [this](bool idle) { tracking_->set_mapper_idle(idle); };
  }
  tracking_->set_mapper_idle(true);
  tracking_->on_new_keyframe = [this](const std::shared_ptr<KeyFrame>& kf) {
    {
      std::lock_guard<std::mutex> lock(records_mutex_);
      all_keyframes_[kf->id()] = kf;
    }
    if (mapping_) mapping_->insert_keyframe(kf);
  };
  if (loop_) loop_->start();
  if (mapping_) mapping_->start();
}

SlamSystem::~SlamSystem() {
  if (mapping_) mapping_->shutdown(false);
  if (loop_) loop_->shutdown(false);
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
  if (simulated_mapping_frames_ > 0 && mapping_)
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
  frames_.push_back(FrameRecord{stamp, ref, r.T_cw * ref->T_wc()});
  return r;
}

bool SlamSystem::wait_until_idle(double timeout_s) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  auto remaining = [&] {
    return std::max(0.0, std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count());
  };
  bool ok = true;
  // A processed KeyFrame goes on to loop closing, whose correction pauses mapping: twice round.
  for (int round = 0; round < 2; ++round) {
    if (mapping_) ok = mapping_->wait_until_idle(remaining()) && ok;
    if (loop_) ok = loop_->wait_until_idle(remaining()) && ok;
  }
  return ok;
}

bool SlamSystem::finish(double timeout_s) {
  if (finished_) return true;
  finished_ = true;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  auto remaining = [&] {
    return std::max(0.0, std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count());
  };
  bool ok = true;
  // Mapping feeds loop closing and a full BA pauses mapping: wait until both are quiet.
  for (int round = 0; round < 3; ++round) {
    if (mapping_) ok = mapping_->wait_until_idle(remaining()) && ok;
    if (loop_) ok = loop_->wait_until_idle(remaining()) && ok;
  }
  if (mapping_) mapping_->shutdown(ok);
  if (loop_) loop_->shutdown(ok);
  if (ok && final_full_ba_iterations_ > 0) {
    // The threads are stopped: the map is ours, but the lock keeps readers (trajectory()) out.
    std::lock_guard<std::mutex> lock(map_->update_mutex());
    const BundleAdjustmentProblem problem = build_full_ba_problem(*map_);
    if (problem.keyframes.size() >= 2) {
      const BundleAdjustmentResult result = run_full_bundle_adjustment(problem, final_full_ba_iterations_);
      if (result.ok) apply_full_ba_result(*map_, result);
      else std::cerr << "[slam] final full BA failed: " << result.message << "; map kept as it was\n";
    }
  }
  return ok;
}

std::shared_ptr<KeyFrame> SlamSystem::keyframe_ever(uint32_t id) const {
  const auto it = all_keyframes_.find(id);
  return it == all_keyframes_.end() ? nullptr : it->second;
}

std::vector<std::pair<double, Eigen::Isometry3d>> SlamSystem::trajectory() const {
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  std::lock_guard<std::mutex> lock(records_mutex_);
  std::vector<std::pair<double, Eigen::Isometry3d>> out;
  out.reserve(frames_.size());
  for (const FrameRecord& f : frames_) {
    std::shared_ptr<KeyFrame> kf = f.reference;
    Eigen::Isometry3d T_c_kf = f.T_c_ref;
    // A culled keyframe is placed relative to its parent at culling time.
    for (int hops = 0; kf && kf->is_bad() && hops < 10000; ++hops) {
      T_c_kf = T_c_kf * kf->T_cp();
      kf = keyframe_ever(kf->parent_id());
    }
    if (!kf) continue;
    out.emplace_back(f.stamp, (T_c_kf * kf->T_cw()).inverse());
  }
  return out;
}

}  // namespace edge_slam
