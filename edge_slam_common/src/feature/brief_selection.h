// Offline selection of the rotated-BRIEF test table (tools/select_brief_pattern.cpp): the
// greedy low-correlation search of the ORB paper (Rublee et al., ICCV 2011), run on oriented
// keypoints of our own extractor. Not used at run time.
#pragma once
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "edge_slam/feature/brief_pattern.h"
#include "edge_slam/feature/orb_extractor.h"

namespace edge_slam {

// Every integer point (x, y) with x^2 + y^2 <= kOrbPatchRadius^2, ordered by y, then x.
const std::vector<cv::Point>& brief_disc_points();
// Index of (x, y) in brief_disc_points(), or -1 when outside the disc.
int brief_disc_index(int x, int y);

// For each keypoint, the smoothed level-image intensity at every disc point after steering
// it by the keypoint angle: exactly the pixels compute_rotated_brief() would compare, so a
// test between disc points i and j gives bit  values[i] < values[j].
struct SteeredSamples {
  int num_points = 0;           // brief_disc_points().size()
  std::vector<uint8_t> values;  // keypoint-major: keypoint k, point i at k * num_points + i
  size_t size() const { return num_points ? values.size() / num_points : 0; }
  const uint8_t* keypoint(size_t k) const { return values.data() + k * num_points; }
};

// Runs the extractor on gray (CV_8UC1) and appends the steered samples of every keypoint it
// returns. The extractor's level images are rebuilt here (same pyramid, same 7x7 sigma-2
// blur), so as a self-check each keypoint's descriptor is recomputed from its samples with
// the compiled-in brief_pattern() and compared with the extractor's output: the return value
// is the number of keypoints whose descriptor differed (0 unless the two drifted apart).
size_t append_steered_samples(const OrbExtractor& extractor, const cv::Mat& gray, SteeredSamples& samples);

// Descriptor (kDescriptorBytes) of keypoint k for an arbitrary table (points inside the disc).
void describe_with_table(const SteeredSamples& samples, size_t k, const std::vector<BriefTest>& table,
                         uint8_t* descriptor);

// `count` candidate tests, both points drawn uniformly from the integer points of the disc
// with SplitMix64(seed); pairs closer than min_separation pixels are redrawn, as are exact
// repeats (also with the two points swapped).
std::vector<BriefTest> draw_candidate_tests(int count, uint64_t seed, int min_separation);

struct BriefSelectionParams {
  int tests = kBriefTests;           // how many to keep
  int start_threshold_steps = 10;    // first |correlation| threshold tried = steps * step
  double threshold_step = 0.02;
};

struct BriefSelectionResult {
  std::vector<BriefTest> tests;        // in selection order
  std::vector<double> ones_fraction;    // P(bit = 1) of each kept test
  double threshold = 0;                // |correlation| bound the kept tests satisfy pairwise
  double max_abs_correlation = 0;      // actual maximum over kept pairs
  size_t keypoints = 0;
  std::vector<int> tried_steps;        // thresholds tried, in units of threshold_step
  std::vector<int> kept_at_step;       // tests the greedy pass kept at each (capped at `tests`)
};

// Evaluates every candidate on every keypoint, orders candidates by |P(1) - 0.5| (ties by
// index), and keeps them greedily while |correlation| with every kept test <= threshold. The
// threshold is lowered step by step while the pass still reaches params.tests, or raised until
// it does; the result is the first params.tests kept at the lowest threshold that reaches it.
// Throws std::runtime_error if even threshold 1 cannot reach it.
BriefSelectionResult select_brief_tests(const SteeredSamples& samples, const std::vector<BriefTest>& candidates,
                                        const BriefSelectionParams& params);

}  // namespace edge_slam
