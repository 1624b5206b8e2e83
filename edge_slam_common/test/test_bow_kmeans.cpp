// One k-means step on binary descriptors: majority vote, cluster recovery, degenerate inputs.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "edge_slam/data/bow_kmeans.h"
#include "edge_slam/feature/descriptor_distance.h"

using namespace edge_slam;

namespace {

std::vector<uint8_t> random_rows(size_t n, std::mt19937& rng) {
  std::vector<uint8_t> rows(n * kDescriptorBytes);
  for (auto& b : rows) b = static_cast<uint8_t>(rng());
  return rows;
}

// Each row is one of `centres` with up to `max_flips` random bits flipped.
std::vector<uint8_t> noisy_copies(const std::vector<uint8_t>& centres, size_t per_centre, int max_flips,
                                  std::mt19937& rng, std::vector<int>* truth) {
  const size_t k = centres.size() / kDescriptorBytes;
  std::vector<uint8_t> rows;
  for (size_t i = 0; i < per_centre; ++i)
    for (size_t c = 0; c < k; ++c) {
      const size_t at = rows.size();
      rows.insert(rows.end(), centres.begin() + c * kDescriptorBytes, centres.begin() + (c + 1) * kDescriptorBytes);
      const int flips = static_cast<int>(rng() % (max_flips + 1));
      for (int f = 0; f < flips; ++f) {
        const int bit = static_cast<int>(rng() % 256);
        rows[at + bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
      }
      if (truth) truth->push_back(static_cast<int>(c));
    }
  return rows;
}

}  // namespace

TEST(BowKmeans, MajorityVotePerBit) {
  std::vector<uint8_t> rows(3 * kDescriptorBytes, 0);
  rows[0] = 0b0011;                      // row 0
  rows[kDescriptorBytes] = 0b0110;       // row 1
  rows[2 * kDescriptorBytes] = 0b0100;   // row 2
  rows[2 * kDescriptorBytes + 31] = 0xFF;
  uint8_t out[kDescriptorBytes];
  bitwise_majority(rows.data(), 3, out);
  EXPECT_EQ(out[0], 0b0110);  // bit 1: 2 votes, bit 2: 2 votes, bits 0 and 3: 1 or 0
  EXPECT_EQ(out[31], 0);      // 1 of 3
  for (int b = 1; b < 31; ++b) EXPECT_EQ(out[b], 0);
}

TEST(BowKmeans, MajorityVoteSurvivesCounterFlushes) {
  // More than 255 rows exercises the packed-lane flush.
  std::vector<uint8_t> rows(1001 * kDescriptorBytes, 0);
  for (size_t i = 0; i < 501; ++i) rows[i * kDescriptorBytes + 7] = 0x80;  // 501 of 1001 set bit 7 of byte 7
  uint8_t out[kDescriptorBytes];
  bitwise_majority(rows.data(), 1001, out);
  EXPECT_EQ(out[7], 0x80);
  for (size_t i = 0; i < 2; ++i) rows[i * kDescriptorBytes + 7] = 0;  // now 499 of 1001
  bitwise_majority(rows.data(), 1001, out);
  EXPECT_EQ(out[7], 0);
}

TEST(BowKmeans, RecoversWellSeparatedClusters) {
  std::mt19937 rng(3);
  const std::vector<uint8_t> centres = random_rows(6, rng);
  std::vector<int> truth;
  const std::vector<uint8_t> rows = noisy_copies(centres, 50, 8, rng, &truth);
  std::mt19937_64 seeding(7);
  const BinaryClusters clusters = cluster_binary_descriptors(rows.data(), truth.size(), 6, 10, seeding);
  ASSERT_EQ(clusters.cluster_count(), 6u);
  // Every true cluster maps to exactly one found cluster and vice versa.
  std::vector<std::set<uint32_t>> found_for_truth(6);
  for (size_t i = 0; i < truth.size(); ++i) found_for_truth[truth[i]].insert(clusters.assignment[i]);
  std::set<uint32_t> used;
  for (const auto& s : found_for_truth) {
    ASSERT_EQ(s.size(), 1u);
    used.insert(*s.begin());
  }
  EXPECT_EQ(used.size(), 6u);
  // Majority of noisy copies is (almost) the centre itself.
  for (size_t c = 0; c < 6; ++c) {
    const uint32_t id = *found_for_truth[c].begin();
    EXPECT_LE(descriptor_distance(&clusters.centroids[id * kDescriptorBytes], &centres[c * kDescriptorBytes]), 2);
  }
}

TEST(BowKmeans, FewerDistinctRowsThanKGivesOneClusterPerValue) {
  std::mt19937 rng(5);
  const std::vector<uint8_t> distinct = random_rows(3, rng);
  const std::vector<uint8_t> rows = noisy_copies(distinct, 4, 0, rng, nullptr);  // 12 rows, 3 values
  std::mt19937_64 seeding(1);
  const BinaryClusters clusters = cluster_binary_descriptors(rows.data(), 12, 10, 10, seeding);
  EXPECT_EQ(clusters.cluster_count(), 3u);
  for (size_t i = 0; i < 12; ++i)
    EXPECT_EQ(descriptor_distance(&rows[i * kDescriptorBytes],
                                  &clusters.centroids[clusters.assignment[i] * kDescriptorBytes]),
              0);
}

TEST(BowKmeans, AssignmentIsNearestCentroid) {
  std::mt19937 rng(11);
  const std::vector<uint8_t> rows = random_rows(400, rng);  // no structure: many moves, iteration cap hit
  std::mt19937_64 seeding(2);
  const BinaryClusters clusters = cluster_binary_descriptors(rows.data(), 400, 8, 3, seeding);
  for (size_t i = 0; i < 400; ++i) {
    const int assigned = descriptor_distance(&rows[i * kDescriptorBytes],
                                             &clusters.centroids[clusters.assignment[i] * kDescriptorBytes]);
    for (size_t c = 0; c < clusters.cluster_count(); ++c)
      EXPECT_LE(assigned, descriptor_distance(&rows[i * kDescriptorBytes], &clusters.centroids[c * kDescriptorBytes]));
  }
}
