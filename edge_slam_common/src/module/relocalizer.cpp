#include "edge_slam/module/relocalizer.h"

#include <unordered_set>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/match/orb_matcher.h"
#include "edge_slam/module/frame_pose.h"
#include "edge_slam/solve/pnp_solver.h"

namespace edge_slam {
namespace {
constexpr int kMinBowMatches = 15;
constexpr int kMinPnpInliers = 10;

void reset_matches(Frame& frame) {
  frame.map_points.assign(frame.size(), nullptr);
  frame.outliers.assign(frame.size(), false);
}

std::unordered_set<uint32_t> matched_ids(const Frame& frame) {
  std::unordered_set<uint32_t> ids;
  for (const auto& mp : frame.map_points)
    if (mp) ids.insert(mp->id());
  return ids;
}
}  // namespace

BowPnpRelocalizer::BowPnpRelocalizer(std::shared_ptr<const Map> map,
                                     std::shared_ptr<const KeyFrameDatabase> database,
                                     std::shared_ptr<const BowVocabulary> vocabulary, int min_inliers)
    : map_(std::move(map)),
      database_(std::move(database)),
      vocabulary_(std::move(vocabulary)),
      min_inliers_(min_inliers) {}

bool BowPnpRelocalizer::relocalize(Frame& frame) {
  if (!vocabulary_ || vocabulary_->empty() || frame.size() == 0) return false;
  frame.compute_bow(*vocabulary_);
  const auto candidates = database_->detect_relocalization_candidates(frame, *map_);
  for (const auto& kf : candidates) {
    if (kf->is_bad()) continue;
    if (try_candidate(frame, kf)) {
      frame.reference_kf = kf;
      return true;
    }
  }
  reset_matches(frame);
  return false;
}

bool BowPnpRelocalizer::try_candidate(Frame& frame, const std::shared_ptr<KeyFrame>& kf) {
  reset_matches(frame);
  const auto kf_points = kf->map_points(*map_);
  const OrbMatcher bow_matcher(0.75f, true);
  if (bow_matcher.search_by_bow(*kf, kf_points, frame) < kMinBowMatches) return false;

  // PnP on the BoW matches.
  const FrameFeatures& f = frame.feat();
  std::vector<PoseObservation> obs;
  std::vector<size_t> keypoint_of;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    if (!frame.map_points[i]) continue;
    obs.push_back(pose_observation(f, i, frame.map_points[i]->position()));
    keypoint_of.push_back(i);
  }
  PnpParams pnp_params;
  pnp_params.min_inliers = kMinPnpInliers;
  const PnpResult pnp = solve_pnp_ransac(f.camera, obs, pnp_params);
  if (!pnp.ok) return false;
  frame.set_pose(pnp.T_cw);
  for (size_t k = 0; k < keypoint_of.size(); ++k)
    if (!pnp.inliers[k]) frame.map_points[keypoint_of[k]] = nullptr;

  int good = optimize_frame_pose(frame);
  if (good < kMinPnpInliers) return false;
  discard_outliers(frame);

  // Not enough yet: project the candidate's other points with the new pose.
  const OrbMatcher proj_matcher(0.9f, true);
  if (good < min_inliers_) {
    const int added = proj_matcher.search_by_projection(frame, *kf, kf_points, matched_ids(frame), 10, 100);
    if (good + added >= min_inliers_) {
      good = optimize_frame_pose(frame);
      if (good > 30 && good < min_inliers_) {  // narrower second pass with the refined pose
        discard_outliers(frame);
        const int more = proj_matcher.search_by_projection(frame, *kf, kf_points, matched_ids(frame), 3, 64);
        if (good + more >= min_inliers_) good = optimize_frame_pose(frame);
      }
    }
  }
  if (good < min_inliers_) return false;
  discard_outliers(frame);
  return true;
}

}  // namespace edge_slam
