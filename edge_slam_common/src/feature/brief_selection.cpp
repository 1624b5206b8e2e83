#include "brief_selection.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include "edge_slam/data/bow_popcount_dispatch.h"
#include "edge_slam/feature/descriptor_distance.h"
#include "edge_slam/feature/image_pyramid.h"
#include "edge_slam/feature/orb_patch.h"
#include "edge_slam/sim/random.h"

namespace edge_slam {
namespace {

// Must match the extractor's descriptor smoothing (orb_extractor.cpp); the self-check in
// append_steered_samples() fails loudly if it ever does not.
cv::Mat smooth_like_extractor(const cv::Mat& level_image) {
  cv::Mat smoothed;
  cv::GaussianBlur(level_image, smoothed, cv::Size(7, 7), 2.0, 2.0, cv::BORDER_REFLECT_101);
  return smoothed;
}

struct DiscIndex {
  std::vector<cv::Point> points;
  std::vector<int> index;  // (y + R) * (2R + 1) + (x + R) -> point index or -1
  DiscIndex() {
    constexpr int R = kOrbPatchRadius;
    index.assign((2 * R + 1) * (2 * R + 1), -1);
    for (int y = -R; y <= R; ++y)
      for (int x = -R; x <= R; ++x)
        if (x * x + y * y <= R * R) {
          index[(y + R) * (2 * R + 1) + (x + R)] = static_cast<int>(points.size());
          points.emplace_back(x, y);
        }
  }
};

const DiscIndex& disc() {
  static const DiscIndex d;
  return d;
}

EDGE_SLAM_POPCNT_CLONES
size_t popcount_words(const uint64_t* a, size_t words) {
  size_t n = 0;
  for (size_t w = 0; w < words; ++w) n += static_cast<size_t>(__builtin_popcountll(a[w]));
  return n;
}

EDGE_SLAM_POPCNT_CLONES
size_t popcount_and(const uint64_t* a, const uint64_t* b, size_t words) {
  size_t n = 0;
  for (size_t w = 0; w < words; ++w) n += static_cast<size_t>(__builtin_popcountll(a[w] & b[w]));
  return n;
}

// Bits of one candidate over all keypoints: bit k set when point-major rows a[k] < b[k].
void pack_bits(const uint8_t* a, const uint8_t* b, size_t n, uint64_t* out) {
  const size_t full = n / 64;
  for (size_t w = 0; w < full; ++w) {
    uint64_t word = 0;
    const uint8_t* pa = a + w * 64;
    const uint8_t* pb = b + w * 64;
    for (int j = 0; j < 64; ++j) word |= static_cast<uint64_t>(pa[j] < pb[j]) << j;
    out[w] = word;
  }
  if (n % 64) {
    uint64_t word = 0;
    for (size_t k = full * 64, j = 0; k < n; ++k, ++j) word |= static_cast<uint64_t>(a[k] < b[k]) << j;
    out[full] = word;
  }
}

}  // namespace

const std::vector<cv::Point>& brief_disc_points() { return disc().points; }

int brief_disc_index(int x, int y) {
  constexpr int R = kOrbPatchRadius;
  if (x < -R || x > R || y < -R || y > R) return -1;
  return disc().index[(y + R) * (2 * R + 1) + (x + R)];
}

size_t append_steered_samples(const OrbExtractor& extractor, const cv::Mat& gray, SteeredSamples& samples) {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  extractor.extract(gray, keypoints, descriptors);
  const std::vector<cv::Point>& points = brief_disc_points();
  samples.num_points = static_cast<int>(points.size());
  if (keypoints.empty()) return 0;

  const std::vector<cv::Mat> pyramid = build_image_pyramid(gray, extractor.inv_scale_factors());
  std::vector<cv::Mat> smoothed(pyramid.size());
  std::vector<BriefTest> committed(brief_pattern().begin(), brief_pattern().end());
  size_t mismatches = 0;
  const size_t first = samples.size();
  samples.values.resize((first + keypoints.size()) * points.size());
  for (size_t k = 0; k < keypoints.size(); ++k) {
    const cv::KeyPoint& kp = keypoints[k];
    const cv::Mat& image = pyramid.at(kp.octave);
    if (smoothed[kp.octave].empty()) smoothed[kp.octave] = smooth_like_extractor(image);
    const cv::Mat& level = smoothed[kp.octave];
    // Invert the extractor's level -> full-resolution mapping (level pixels are integers).
    const float to_full_x = static_cast<float>(gray.cols) / image.cols;
    const float to_full_y = static_cast<float>(gray.rows) / image.rows;
    const int x = cvRound((kp.pt.x + 0.5f) / to_full_x - 0.5f);
    const int y = cvRound((kp.pt.y + 0.5f) / to_full_y - 0.5f);
    // Same float arithmetic and rounding (to nearest, ties to even) as compute_rotated_brief.
    const float angle = kp.angle * static_cast<float>(CV_PI / 180.0);
    const float c = std::cos(angle), s = std::sin(angle);
    const int step = static_cast<int>(level.step1());
    const uint8_t* center = level.ptr<uint8_t>(y) + x;
    uint8_t* out = samples.values.data() + (first + k) * points.size();
    for (size_t i = 0; i < points.size(); ++i) {
      const float px = static_cast<float>(points[i].x), py = static_cast<float>(points[i].y);
      const float xc = px * c, ys = py * s, xs = px * s, yc = py * c;
      out[i] = center[cvRound(xs + yc) * step + cvRound(xc - ys)];
    }
    uint8_t descriptor[kDescriptorBytes];
    describe_with_table(samples, first + k, committed, descriptor);
    mismatches += std::memcmp(descriptor, descriptors.ptr<uint8_t>(static_cast<int>(k)), kDescriptorBytes) != 0;
  }
  return mismatches;
}

void describe_with_table(const SteeredSamples& samples, size_t k, const std::vector<BriefTest>& table,
                         uint8_t* descriptor) {
  std::memset(descriptor, 0, kDescriptorBytes);
  const uint8_t* v = samples.keypoint(k);
  for (size_t t = 0; t < table.size() && t < static_cast<size_t>(8 * kDescriptorBytes); ++t) {
    const int a = brief_disc_index(table[t].x1, table[t].y1);
    const int b = brief_disc_index(table[t].x2, table[t].y2);
    if (a < 0 || b < 0) throw std::invalid_argument("describe_with_table: test point outside the disc");
    descriptor[t / 8] |= static_cast<uint8_t>(v[a] < v[b]) << (t % 8);
  }
}

std::vector<BriefTest> draw_candidate_tests(int count, uint64_t seed, int min_separation) {
  const std::vector<cv::Point>& points = brief_disc_points();
  const int n = static_cast<int>(points.size());
  // Distinct unordered pairs with separation >= min_separation bound what can be drawn.
  long long available = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const cv::Point d = points[i] - points[j];
      available += d.x * d.x + d.y * d.y >= min_separation * min_separation;
    }
  if (count < 0 || count > available)
    throw std::invalid_argument("draw_candidate_tests: only " + std::to_string(available) + " distinct tests exist");

  SplitMix64 rng(seed);
  std::set<std::tuple<int, int>> seen;  // unordered pair of point indices
  std::vector<BriefTest> tests;
  tests.reserve(count);
  while (static_cast<int>(tests.size()) < count) {
    const int a = rng.integer(0, n - 1);
    const int b = rng.integer(0, n - 1);
    const cv::Point d = points[a] - points[b];
    if (d.x * d.x + d.y * d.y < min_separation * min_separation || a == b) continue;
    if (!seen.insert({std::min(a, b), std::max(a, b)}).second) continue;
    tests.push_back({static_cast<int8_t>(points[a].x), static_cast<int8_t>(points[a].y),
                     static_cast<int8_t>(points[b].x), static_cast<int8_t>(points[b].y)});
  }
  return tests;
}

BriefSelectionResult select_brief_tests(const SteeredSamples& samples, const std::vector<BriefTest>& candidates,
                                        const BriefSelectionParams& params) {
  const size_t n = samples.size();
  const size_t num_points = static_cast<size_t>(samples.num_points);
  if (n < 2) throw std::runtime_error("select_brief_tests: need at least 2 keypoints");
  if (params.tests <= 0 || params.threshold_step <= 0 || params.start_threshold_steps < 0)
    throw std::invalid_argument("select_brief_tests: bad parameters");

  // Point-major copy, so each candidate compares two contiguous rows.
  std::vector<uint8_t> by_point(num_points * n);
  for (size_t k = 0; k < n; ++k) {
    const uint8_t* v = samples.keypoint(k);
    for (size_t i = 0; i < num_points; ++i) by_point[i * n + k] = v[i];
  }

  const size_t words = (n + 63) / 64;
  std::vector<uint64_t> bits(candidates.size() * words);
  std::vector<double> ones(candidates.size());
  for (size_t c = 0; c < candidates.size(); ++c) {
    const int a = brief_disc_index(candidates[c].x1, candidates[c].y1);
    const int b = brief_disc_index(candidates[c].x2, candidates[c].y2);
    if (a < 0 || b < 0) throw std::invalid_argument("select_brief_tests: candidate point outside the disc");
    uint64_t* row = bits.data() + c * words;
    pack_bits(by_point.data() + a * n, by_point.data() + b * n, n, row);
    ones[c] = static_cast<double>(popcount_words(row, words)) / n;
  }
  std::vector<uint8_t>().swap(by_point);

  std::vector<size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return std::abs(ones[a] - 0.5) < std::abs(ones[b] - 0.5); });

  auto correlation = [&](size_t a, size_t b) {
    const double p11 = static_cast<double>(popcount_and(bits.data() + a * words, bits.data() + b * words, words)) / n;
    return (p11 - ones[a] * ones[b]) /
           std::sqrt(ones[a] * (1 - ones[a]) * ones[b] * (1 - ones[b]));
  };
  // One greedy pass; stops as soon as params.tests are kept.
  auto greedy = [&](double threshold) {
    std::vector<size_t> kept;
    for (size_t c : order) {
      if (ones[c] <= 0.0 || ones[c] >= 1.0) continue;  // constant bit: no information
      bool ok = true;
      for (size_t t : kept)
        if (std::abs(correlation(c, t)) > threshold) {
          ok = false;
          break;
        }
      if (!ok) continue;
      kept.push_back(c);
      if (static_cast<int>(kept.size()) == params.tests) break;
    }
    return kept;
  };

  BriefSelectionResult result;
  result.keypoints = n;
  const int max_steps = static_cast<int>(std::ceil(1.0 / params.threshold_step));
  auto run = [&](int steps) {
    std::vector<size_t> kept = greedy(std::min(1.0, steps * params.threshold_step));
    result.tried_steps.push_back(steps);
    result.kept_at_step.push_back(static_cast<int>(kept.size()));
    return kept;
  };
  int steps = std::min(params.start_threshold_steps, max_steps);
  std::vector<size_t> best = run(steps);
  int best_steps = steps;
  if (static_cast<int>(best.size()) == params.tests) {
    while (steps > 0) {  // lower while the pass still reaches the target
      std::vector<size_t> kept = run(--steps);
      if (static_cast<int>(kept.size()) < params.tests) break;
      best = std::move(kept);
      best_steps = steps;
    }
  } else {
    while (static_cast<int>(best.size()) < params.tests) {
      if (steps >= max_steps)
        throw std::runtime_error("select_brief_tests: fewer than " + std::to_string(params.tests) +
                                 " usable candidates");
      best = run(++steps);
      best_steps = steps;
    }
  }

  result.threshold = std::min(1.0, best_steps * params.threshold_step);
  for (size_t i = 0; i < best.size(); ++i) {
    result.tests.push_back(candidates[best[i]]);
    result.ones_fraction.push_back(ones[best[i]]);
    for (size_t j = 0; j < i; ++j)
      result.max_abs_correlation = std::max(result.max_abs_correlation, std::abs(correlation(best[i], best[j])));
  }
  return result;
}

}  // namespace edge_slam
