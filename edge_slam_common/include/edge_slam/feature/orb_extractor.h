// ORB features as ORB-SLAM2 extracts them: FAST on a scale pyramid, spread evenly per
// level with a quadtree, oriented by intensity centroid, described by steered BRIEF.
//
// Deliberate differences from ORB-SLAM2 (all our own code):
//  - the BRIEF test table is our own (brief_pattern.cpp), so descriptors are NOT
//    compatible with vocabularies trained on ORB-SLAM2/OpenCV descriptors (e.g. ORBvoc.txt);
//  - FAST at the initial threshold runs once per level, the low-threshold retry per empty
//    30x30 cell; level pixels map to full resolution as (x + 0.5) * ratio - 0.5 with the
//    exact level size ratio (unbiased, unlike x * scale);
//  - each level returns at most its budget (quadtree overshoot trimmed by response), and the
//    per-level budget sums exactly to num_features.
//
// Thread safety: extract() is const and touches no shared mutable state, so one
// extractor may serve several threads at once.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

#include "edge_slam/feature/intensity_centroid.h"
#include "edge_slam/feature/orb_params.h"
#include "edge_slam/feature/pyramid_scales.h"

namespace edge_slam {

class OrbExtractor {
 public:
  // Throws std::invalid_argument for unusable parameters (see validate_orb_params).
  explicit OrbExtractor(const OrbParams& params = OrbParams());

  // gray: CV_8UC1 (throws std::invalid_argument otherwise); an empty, tiny or textureless
  // image yields 0 keypoints.
  // keypoints: full-resolution pixel coordinates of the input image (a level pixel centre
  // is mapped through the exact resize ratio of its level), octave = pyramid level,
  // angle in degrees [0, 360), size = 31 * scale of the level, response = FAST score.
  // Keypoints are grouped by level, finest first.
  // descriptors: N x 32, CV_8U, row i for keypoints[i].
  void extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const;

  const OrbParams& params() const { return params_; }
  int num_levels() const { return params_.num_levels; }
  float scale_factor() const { return params_.scale_factor; }
  const std::vector<float>& scale_factors() const { return scales_.scale; }  // 1, s, s^2, ...
  const std::vector<float>& inv_scale_factors() const { return scales_.inv_scale; }
  const std::vector<float>& level_sigma2() const { return scales_.sigma2; }  // scale_factor(level)^2
  const std::vector<float>& inv_level_sigma2() const { return scales_.inv_sigma2; }
  // Keypoints wanted on each level; their sum is num_features.
  const std::vector<int>& features_per_level() const { return features_per_level_; }

 private:
  OrbParams params_;
  PyramidScales scales_;
  std::vector<int> features_per_level_;
  CentroidDisc disc_;  // orientation disc, radius kOrbPatchRadius
};

}  // namespace edge_slam
