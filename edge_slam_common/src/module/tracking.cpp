#include "edge_slam/module/tracking.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <optional>
#include <sstream>
#include <unordered_set>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/rolling_shutter.h"
#include "edge_slam/match/orb_matcher.h"
#include "edge_slam/module/frame_pose.h"
#include "edge_slam/module/keyframe_decision.h"
#include "edge_slam/module/last_frame_depth_points.h"
#include "edge_slam/module/update_carry_over.h"
#include "edge_slam/util/flat_id_set.h"

namespace edge_slam {
namespace {

// ORB-SLAM2 RGB-D constants.
// Motion-model search window at level 0: a tight first try, then a wide retry when the
// velocity changed (ORB-SLAM2 uses 15 then 30 for RGB-D; 7 first was more accurate here).
constexpr float kMotionModelWindow = 7.f;
constexpr float kMotionModelRetryWindow = 30.f;
constexpr int kMinMotionMatches = 20;
constexpr int kMinBowMatches = 15;
constexpr int kMinMapMatchesAfterPose = 10;
// Share of the tight-window matches that must survive the pose optimisation for the constant-
// velocity hypothesis to stand alone (typical frames keep 70-80%, a wrongly predicted one 20-40%).
constexpr double kMinMotionInlierShare = 0.5;
constexpr float kLocalMapWindow = 3.f;        // 5 right after a relocalization
constexpr float kMinViewCos = 0.5f;           // 60 degrees off the mean viewing direction

void clear_matches(Frame& frame) {
  frame.map_points.assign(frame.size(), nullptr);
  frame.outliers.assign(frame.size(), false);
}

bool finite_pose(const Eigen::Isometry3d& T) { return T.matrix().allFinite(); }

// CPU time of the calling thread: per-frame cost independent of other processes' load.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

}  // namespace

const char* to_string(TrackingState s) {
  switch (s) {
    case TrackingState::kNotInitialized: return "NOT_INITIALIZED";
    case TrackingState::kOk: return "OK";
    case TrackingState::kLost: return "LOST";
  }
  return "?";
}

std::string describe(const TrackingDiagnostics& d) {
  std::ostringstream out;
  out << "path=" << d.path << " last_frame_points=" << d.last_frame_points
      << " initial_matches=" << d.initial_matches << " initial_inliers=" << d.initial_inliers
      << " local_map_points=" << d.local_map_points << " matches_before_final=" << d.matches_before_final
      << " reference_kf=" << (d.reference_kf_id == kNoId ? -1 : static_cast<long>(d.reference_kf_id))
      << " reference_points=" << d.reference_points << " keyframe_conditions=" << d.keyframe_conditions
      << " weak_pose=" << d.weak_pose << std::fixed << std::setprecision(2);
  if (d.has_prediction)
    out << " prediction_error_cm=" << d.prediction_error_m * 100 << " prediction_error_deg=" << d.prediction_error_deg;
  out << " last_frame_depth_points=" << d.last_frame_depth_points << " depth_point_inliers=" << d.depth_point_inliers;
  return out.str();
}

Tracking::Tracking(const PinholeCamera& camera, const OrbParams& orb, const TrackingParams& params,
                   std::shared_ptr<Map> map, std::shared_ptr<KeyFrameDatabase> database,
                   std::shared_ptr<const BowVocabulary> vocabulary, RgbEncoding encoding)
    : camera_(camera),
      params_(params),
      extractor_(orb),
      encoding_(encoding),
      map_(std::move(map)),
      database_(std::move(database)),
      vocabulary_(std::move(vocabulary)) {
  if (vocabulary_ && !vocabulary_->empty())
    relocalizer_ = std::make_shared<BowPnpRelocalizer>(map_, database_, vocabulary_,
                                                       params_.min_inliers_after_relocalization);
}

void Tracking::reset() {
  std::lock_guard<std::mutex> lock(map_->update_mutex());
  map_->clear();
  database_->clear();
  state_ = TrackingState::kNotInitialized;
  last_frame_ = Frame();
  last_frame_tracked_ = false;
  has_velocity_ = false;
  reference_kf_.reset();
  relocalized_before_ = false;
}

int Tracking::relink_after_map_update(const Map* old_map, const std::unordered_map<uint32_t, uint32_t>* replaced_by) {
  std::lock_guard<std::mutex> lock(map_->update_mutex());
  const std::shared_ptr<KeyFrame> old_reference = last_frame_.reference_kf;
  int followed = 0;
  for (size_t i = 0; i < last_frame_.map_points.size(); ++i) {
    auto& mp = last_frame_.map_points[i];
    if (!mp) continue;
    std::shared_ptr<MapPoint> now = map_->map_point(mp->id());
    if (!now && replaced_by) {
      if (const auto it = replaced_by->find(mp->id()); it != replaced_by->end()) {
        now = map_->map_point(it->second);
        followed += now ? 1 : 0;
      }
    }
    mp = std::move(now);
  }
  auto relink_kf = [&](std::shared_ptr<KeyFrame>& kf) {
    if (kf) kf = map_->keyframe(kf->id());
  };
  relink_kf(last_frame_.reference_kf);
  relink_kf(reference_kf_);
  if (!reference_kf_) {  // fall back to the newest keyframe of the new map
    const auto kfs = map_->keyframes();
    if (!kfs.empty()) reference_kf_ = kfs.back();
  }
  if (!last_frame_tracked_) return followed;
  if (last_frame_.reference_kf && old_map) return followed;  // predict_last_frame_pose moves it with its reference
  // The reference is gone (or the old poses are unknown): correct the last frame by the change
  // at a KeyFrame both maps hold, then anchor it on the new reference.
  if (old_map && old_reference) {
    uint32_t anchor = kNoId;
    if (map_->keyframe(old_reference->parent_id())) anchor = old_reference->parent_id();
    for (uint32_t id : old_reference->ordered_neighbours())
      if (anchor == kNoId && map_->keyframe(id) && old_map->keyframe(id)) anchor = id;
    if (anchor != kNoId) {
      const Eigen::Isometry3d C = map_correction_at(*map_, *old_map, anchor);
      last_frame_.set_pose(last_frame_.T_cw() * C.inverse());
    }
  }
  if (!last_frame_.reference_kf) last_frame_.reference_kf = reference_kf_;
  if (last_frame_.reference_kf) last_relative_to_ref_ = last_frame_.T_cw() * last_frame_.reference_kf->T_wc();
  return followed;
}

TrackingResult Tracking::track_rgbd(const cv::Mat& color, const cv::Mat& depth, double stamp) {
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = thread_cpu_ms();
  StageClock stage_clock(TrackingStage::kExtract);
  Frame frame;
  try {
    frame = Frame::from_rgbd(next_frame_id_++, stamp, color, depth, camera_, extractor_, encoding_);
  } catch (const std::exception& e) {
    ++counters_.frames;
    ++counters_.rejected_inputs;
    TrackingResult r;
    r.state = state_;
    r.message = std::string("input rejected: ") + e.what();
    r.input_rejected = true;
    return r;
  }
  TrackingResult r = track_frame(std::move(frame));
  r.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  r.cpu_ms = thread_cpu_ms() - c0;
  r.stages = stage_clock.read();
  return r;
}

TrackingResult Tracking::track_frame(Frame frame) {
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = thread_cpu_ms();
  std::optional<StageClock> own_clock;  // track_rgbd installed one already
  if (!StageClock::active()) own_clock.emplace(TrackingStage::kMatch);
  StageScope match_stage(TrackingStage::kMatch);  // whatever no other stage claims
  std::lock_guard<std::mutex> map_lock(map_->update_mutex());
  ++counters_.frames;
  next_frame_id_ = std::max(next_frame_id_, frame.id + 1);
  TrackingResult result;
  result.frame_id = frame.id;
  result.keypoints = static_cast<int>(frame.size());

  bool ok = false;
  int inliers = 0;
  Eigen::Isometry3d predicted_T_cw = Eigen::Isometry3d::Identity();
  const std::shared_ptr<const FrameFeatures> measured_features = frame.features;  // before compensation
  TrackingDiagnostics& diag = result.diag;
  if (state_ == TrackingState::kNotInitialized) {
    std::string why;
    diag.path = "init";
    ok = initialize(frame, why);
    if (ok) {
      state_ = TrackingState::kOk;
      result.new_keyframe = true;
      inliers = frame.num_matched();
    } else {
      result.message = why;
    }
  } else {
    if (state_ == TrackingState::kOk) {
      predict_last_frame_pose(diag);
      if (has_velocity_ && last_frame_tracked_) {
        predicted_T_cw = velocity_ * last_frame_.T_cw();
        diag.has_prediction = true;
        // Rolling shutter, first pass: assume the previous frame's velocity.
        frame.features = compensate_rolling_shutter(measured_features, velocity_per_second_);
        ok = track_with_motion_model(frame, diag);
      }
      if (!ok) ok = track_reference_keyframe(frame, diag);
      if (!ok) result.message = "motion model and reference keyframe tracking failed";
    } else {
      diag.path = "relocalization";
      ok = relocalizer_ && relocalizer_->relocalize(frame);
      if (ok) {
        result.relocalized = true;
        relocalized_before_ = true;
        last_relocalization_frame_id_ = frame.id;
        ++counters_.relocalizations;
        reference_kf_ = frame.reference_kf;
      } else {
        result.message = relocalizer_ ? "relocalization failed" : "lost (relocalization unavailable)";
      }
    }
    if (ok) {
      if (!frame.reference_kf) frame.reference_kf = reference_kf_;
      ok = track_local_map(frame, inliers, diag);
      if (ok) recompensate_rolling_shutter(frame, measured_features);
      if (!ok) result.message = "local map tracking found too few inliers (" + std::to_string(inliers) + ")";
    }
    if (ok && !finite_pose(frame.T_cw())) {
      ok = false;
      result.message = "non-finite pose";
    }
    // The last frame's depth points helped place this frame; its KeyFrame decision, its new
    // points and the next frame's search use map points only.
    diag.depth_point_inliers = drop_depth_points(frame);
    if (ok) {
      if (last_frame_tracked_) {
        velocity_ = frame.T_cw() * last_frame_.T_wc();
        velocity_per_second_ = CameraVelocity::from_motion(velocity_, frame.stamp - last_frame_.stamp);
        has_velocity_ = true;
      } else {
        has_velocity_ = false;
      }
      state_ = TrackingState::kOk;
      if (diag.has_prediction) {
        const Eigen::Isometry3d d = predicted_T_cw * frame.T_wc();
        diag.prediction_error_m = (frame.camera_center() - predicted_T_cw.inverse().translation()).norm();
        diag.prediction_error_deg = Eigen::AngleAxisd(d.rotation()).angle() * 180.0 / M_PI;
      }
      // A pose the matches barely support (blur, a wrong prediction) must not become a KeyFrame:
      // its new points would be placed from a wrong pose and the frames after it would track on
      // them, locking the error into the map. The next well-tracked frame makes the KeyFrame.
      const bool keyframe_wanted = decide_keyframe(frame, inliers, diag);  // fills diag.tracked_close
      const bool few_inliers = diag.matches_before_final > 0 &&
                               inliers + diag.depth_point_inliers <
                                   params_.weak_pose_inlier_share * diag.matches_before_final;
      // Few close points and a pose far from where the motion model put it: the optimisation may
      // have settled on a wrong pose (too little support to tell), so this frame's points must
      // not be placed from it. When the motion was real, the next frame confirms it.
      const bool far_and_thin = params_.weak_pose_max_departure_m > 0 && diag.has_prediction &&
                                diag.prediction_error_m > params_.weak_pose_max_departure_m &&
                                diag.tracked_close < params_.keyframe.close_points_tracked;
      diag.weak_pose = few_inliers || far_and_thin;
      if (diag.weak_pose) ++counters_.weak_frames;
      if (keyframe_wanted && !diag.weak_pose) {
        create_keyframe(frame, false);
        result.new_keyframe = true;
      }
    } else {
      if (state_ == TrackingState::kOk) ++counters_.times_lost;
      state_ = TrackingState::kLost;
      has_velocity_ = false;
    }
  }

  if (ok) {
    ++counters_.frames_tracked;
    result.pose_valid = true;
    result.T_cw = frame.T_cw();
    if (frame.reference_kf) last_relative_to_ref_ = frame.T_cw() * frame.reference_kf->T_wc();
  }
  result.state = state_;
  result.inliers = inliers;
  last_frame_tracked_ = ok;
  last_frame_weak_ = ok && diag.weak_pose;
  last_frame_ = std::move(frame);
  result.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  result.cpu_ms = thread_cpu_ms() - c0;
  result.stages = StageClock::active()->read();
  return result;
}

bool Tracking::initialize(Frame& frame, std::string& why) {
  last_decision_ = KeyFrameDecisionInput();
  if (static_cast<int>(frame.size()) < params_.min_initial_keypoints) {
    why = "not initialised: " + std::to_string(frame.size()) + " keypoints (need " +
          std::to_string(params_.min_initial_keypoints) + ")";
    return false;
  }
  int with_depth = 0;
  for (size_t i = 0; i < frame.size(); ++i) with_depth += frame.feat().has_depth(i) ? 1 : 0;
  if (with_depth < params_.min_inliers_after_relocalization) {
    why = "not initialised: only " + std::to_string(with_depth) + " keypoints with valid depth";
    return false;
  }
  frame.set_pose(Eigen::Isometry3d::Identity());
  clear_matches(frame);
  create_keyframe(frame, true);
  map_->set_reference_map_points(map_->map_points());
  return true;
}

void Tracking::predict_last_frame_pose(TrackingDiagnostics& diag) {
  // The reference keyframe may have been moved by local BA / loop closing since.
  if (last_frame_tracked_ && last_frame_.reference_kf && !last_frame_.reference_kf->is_bad())
    last_frame_.set_pose(last_relative_to_ref_ * last_frame_.reference_kf->T_cw());
  // A KeyFrame made map points from its depth already; any other frame lends its depth for one frame.
  const bool lend_depth = params_.last_frame_depth_points == TrackingParams::LastFrameDepthPoints::kOn;
  if (lend_depth && last_frame_tracked_ && last_frame_.has_pose() && last_keyframe_frame_id_ != last_frame_.id)
    diag.last_frame_depth_points =
        add_depth_points(last_frame_, camera_.th_depth, params_.new_points_per_keyframe);
}

bool Tracking::track_with_motion_model(Frame& frame, TrackingDiagnostics& diag) {
  const OrbMatcher matcher(0.9f, true);
  const Eigen::Isometry3d predicted = velocity_ * last_frame_.T_cw();
  for (size_t i = 0; i < last_frame_.map_points.size(); ++i) {
    const auto& mp = last_frame_.map_points[i];
    diag.last_frame_points += mp && !last_frame_.outliers[i] && !mp->is_bad();
  }
  // One hypothesis: the matches within `window` of the prediction, then the pose they support.
  auto hypothesis = [&](float window) {
    frame.set_pose(predicted);
    clear_matches(frame);
    const int n = matcher.search_by_projection(frame, last_frame_, window);
    MotionHypothesis h;
    h.window = window;
    h.matches = n;
    if (n >= kMinMotionMatches && optimize_frame_pose(frame) >= 0) {
      h.inliers = discard_outliers(frame);  // map points only
      h.depth_inliers = count_depth_points(frame);
    }
    h.pose = frame.T_cw();
    h.map_points = frame.map_points;
    h.outliers = frame.outliers;
    return h;
  };
  // A pose stands on enough map points, or (with the last frame's depth points, as ORB-SLAM2's
  // localization mode) on enough matches overall: the Local-Map search then decides.
  auto found_pose = [](const MotionHypothesis& h) {
    return h.inliers >= kMinMapMatchesAfterPose ||
           (h.depth_inliers > 0 && h.inliers + h.depth_inliers >= kMinMotionMatches);
  };
  MotionHypothesis best = hypothesis(kMotionModelWindow);
  diag.path = "motion";
  // The tight window assumes the velocity held. When it did not (an acceleration in a fast turn,
  // or a previous pose that was itself weak), the true matches lie outside it and the nearest
  // look-alikes inside it support a wrong pose: few of the matches survive the optimisation.
  // Then the same prediction is searched widely as well and the better-supported pose is kept.
  const bool supported = found_pose(best) &&
                         best.inliers + best.depth_inliers >= kMinMotionInlierShare * best.matches &&
                         !last_frame_weak_;
  if (!supported) {
    MotionHypothesis wide = hypothesis(kMotionModelRetryWindow);
    ++counters_.wide_motion_searches;
    if (wide.inliers + wide.depth_inliers > best.inliers + best.depth_inliers) {
      best = std::move(wide);
      diag.path = "motion_wide";
    }
  }
  frame.set_pose(best.pose);
  frame.map_points = std::move(best.map_points);
  frame.outliers = std::move(best.outliers);
  diag.initial_matches = best.matches;
  diag.initial_inliers = best.inliers;
  return found_pose(best);
}

void Tracking::recompensate_rolling_shutter(Frame& frame, const std::shared_ptr<const FrameFeatures>& measured) {
  if (camera_.rolling_shutter_readout == 0 || !last_frame_tracked_) return;
  // Second pass: the motion from the last frame to this frame's tracked pose is closer in time
  // to this exposure than the previous frame's velocity. Same keypoints, so the matches stay.
  frame.features = compensate_rolling_shutter(
      measured, CameraVelocity::from_motion(frame.T_cw() * last_frame_.T_wc(), frame.stamp - last_frame_.stamp));
  optimize_frame_pose(frame);
}

bool Tracking::track_reference_keyframe(Frame& frame, TrackingDiagnostics& diag) {
  diag.path = "reference";
  if (!reference_kf_ || !last_frame_.has_pose()) return false;
  clear_matches(frame);
  frame.set_pose(last_frame_.T_cw());
  if (vocabulary_ && !vocabulary_->empty()) {
    frame.compute_bow(*vocabulary_);
    const OrbMatcher matcher(0.7f, true);
    diag.initial_matches = matcher.search_by_bow(*reference_kf_, reference_kf_->map_points(*map_), frame);
    if (diag.initial_matches < kMinBowMatches) return false;
  } else {
    // No vocabulary: assume no motion and search the last frame's points widely.
    const OrbMatcher matcher(0.9f, true);
    diag.initial_matches = matcher.search_by_projection(frame, last_frame_, kMotionModelRetryWindow);
    if (diag.initial_matches < kMinMotionMatches) return false;
  }
  if (optimize_frame_pose(frame) < 0) return false;
  diag.initial_inliers = discard_outliers(frame);
  return diag.initial_inliers >= kMinMapMatchesAfterPose;
}

int Tracking::search_local_points(Frame& frame, const LocalMap& local) {
  FlatIdSet in_frame;  // looked up once per local point (~10^4): no node chasing
  in_frame.reserve(frame.map_points.size());
  for (auto& mp : frame.map_points) {
    if (!mp) continue;
    if (mp->is_bad()) {
      mp = nullptr;
      continue;
    }
    mp->increase_visible();
    in_frame.insert(mp->id());
  }
  std::vector<ProjectedPoint> projected;
  projected.reserve(local.points.size());
  constexpr size_t kPrefetchAhead = 8;  // points: enough to cover a cache miss
  for (size_t k = 0; k < std::min(kPrefetchAhead, local.points.size()); ++k) local.points[k]->prefetch_geometry();
  for (size_t k = 0; k < local.points.size(); ++k) {
    if (k + kPrefetchAhead < local.points.size()) local.points[k + kPrefetchAhead]->prefetch_geometry();
    const auto& mp = local.points[k];
    if (mp->is_bad() || in_frame.contains(mp->id())) continue;
    ProjectedPoint p;
    if (project_into_frame(frame, mp, kMinViewCos, p)) {
      mp->increase_visible();
      projected.push_back(std::move(p));
    }
  }
  if (projected.empty()) return 0;
  const bool just_relocalized = relocalized_before_ && frame.id < last_relocalization_frame_id_ + 2;
  const OrbMatcher matcher(0.8f, true);
  matcher.search_by_projection(frame, projected, just_relocalized ? 5.f : kLocalMapWindow);
  return static_cast<int>(projected.size());
}

bool Tracking::track_local_map(Frame& frame, int& inliers, TrackingDiagnostics& diag) {
  StageScope stage(TrackingStage::kLocalMap);
  inliers = 0;
  LocalMap local = build_local_map(frame, *map_, static_cast<size_t>(params_.max_local_keyframes));
  if (local.reference) {
    reference_kf_ = local.reference;
    frame.reference_kf = local.reference;
  }
  diag.local_map_points = search_local_points(frame, local);
  diag.matches_before_final = frame.num_matched();
  map_->set_reference_map_points(std::move(local.points));  // moved, not copied: ~10^4 points
  if (optimize_frame_pose(frame) < 0) return false;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp || frame.outliers[i]) continue;
    mp->increase_found();
    if (mp->num_observations() > 0) ++inliers;
  }
  const bool recent_relocalization =
      relocalized_before_ &&
      frame.id < last_relocalization_frame_id_ +
                     static_cast<uint64_t>(params_.keyframe.min_frames_after_relocalization);
  const int needed = recent_relocalization ? params_.min_inliers_after_relocalization : params_.min_inliers;
  return inliers >= needed;
}

bool Tracking::decide_keyframe(const Frame& frame, int inliers, TrackingDiagnostics& diag) const {
  StageScope stage(TrackingStage::kKeyFrame);
  if (!reference_kf_) return true;
  const size_t n_kfs = map_->num_keyframes();
  KeyFrameDecisionInput in;
  in.frame_id = frame.id;
  in.relocalized_before = relocalized_before_;
  in.last_relocalization_frame_id = last_relocalization_frame_id_;
  in.last_keyframe_frame_id = last_keyframe_frame_id_;
  in.mapper_idle = mapper_idle_;
  in.tracked_points = inliers;
  in.depth_point_inliers = diag.depth_point_inliers;
  const int min_obs = std::min(params_.reference_min_observations, n_kfs <= 2 ? 2 : 1000);
  in.reference_tracked_points = reference_kf_->tracked_map_points(*map_, min_obs, params_.depth_counts_twice);
  const FrameFeatures& f = frame.feat();
  for (size_t i = 0; i < frame.size(); ++i) {
    if (!f.is_close(i)) continue;
    if (frame.map_points[i] && !frame.outliers[i])
      ++in.tracked_close_points;
    else
      ++in.untracked_close_points;
  }
  diag.reference_points = in.reference_tracked_points;
  diag.reference_kf_id = reference_kf_->id();
  last_decision_ = in;
  diag.tracked_close = in.tracked_close_points;
  diag.untracked_close = in.untracked_close_points;
  diag.keyframe_conditions = keyframe_condition_bits(params_.keyframe, in);
  return need_new_keyframe(params_.keyframe, in, params_.conditions);
}

std::shared_ptr<KeyFrame> Tracking::create_keyframe(Frame& frame, bool all_depth_points) {
  StageScope stage(TrackingStage::kKeyFrame);
  if (vocabulary_ && !vocabulary_->empty()) frame.compute_bow(*vocabulary_);
  auto kf = std::make_shared<KeyFrame>(map_->new_keyframe_id(), frame);
  map_->add_keyframe(kf);
  const FrameFeatures& f = frame.feat();

  // Observations of the points this frame tracks.
  std::vector<std::shared_ptr<MapPoint>> tracked;
  for (size_t i = 0; i < frame.size(); ++i) {
    auto& mp = frame.map_points[i];
    if (!mp) continue;
    if (frame.outliers[i] || mp->is_bad() || mp->index_in(kf->id()) >= 0) {
      mp = nullptr;
      frame.outliers[i] = false;
      continue;
    }
    kf->set_map_point_id(i, mp->id());
    mp->add_observation(kf->id(), static_cast<int>(i));
    tracked.push_back(mp);
  }

  // New points from the closest unmatched keypoints with depth: every close one, and
  // at least new_points_per_keyframe even if far (all of them at initialisation).
  std::vector<std::pair<float, size_t>> by_depth;
  for (size_t i = 0; i < frame.size(); ++i)
    if (f.has_depth(i)) by_depth.emplace_back(f.depth[i], i);
  std::sort(by_depth.begin(), by_depth.end());
  int points = 0;
  std::vector<size_t> sources;
  for (const auto& [z, i] : by_depth) {
    if (!all_depth_points && z > camera_.th_depth && points > params_.new_points_per_keyframe) break;
    ++points;
    if (!frame.map_points[i]) sources.push_back(i);
  }
  // Ids in keypoint order: the KeyFrame record then names them by the first one alone
  // (KeyFrame.msg, format 5).
  std::sort(sources.begin(), sources.end());
  for (size_t i : sources) {
    auto mp = std::make_shared<MapPoint>(map_->new_map_point_id(), frame.unproject_world(i), kf->id());
    mp->set_descriptor(f.descriptor(i));
    mp->add_observation(kf->id(), static_cast<int>(i));
    kf->set_map_point_id(i, mp->id());
    map_->add_map_point(mp);
    mp->update_normal_and_depth(*map_);
    frame.map_points[i] = mp;
    frame.outliers[i] = false;
  }
  for (const auto& mp : tracked) {
    mp->update_descriptor(*map_);
    mp->update_normal_and_depth(*map_);
  }
  kf->update_connections(*map_);
  if (kf->has_bow()) database_->add(kf);
  reference_kf_ = kf;
  frame.reference_kf = kf;
  last_keyframe_frame_id_ = frame.id;
  ++counters_.keyframes_created;
  if (on_new_keyframe) on_new_keyframe(kf);
  return kf;
}

}  // namespace edge_slam
