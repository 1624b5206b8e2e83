// k-means++ / k-medians on 256-bit descriptors. Hot loops are popcount distances and a packed
// bit-vote counter, so a full k=10, L=6 training on ~300k descriptors takes seconds.
#include "edge_slam/data/bow_kmeans.h"

#include <array>
#include <cstring>
#include <limits>

#include "edge_slam/data/bow_popcount_dispatch.h"
#include "edge_slam/feature/descriptor_distance.h"

namespace edge_slam {
namespace {

// kSpread[v] has byte j equal to bit j of v: adding it to a uint64 counts 8 bits at once.
constexpr std::array<uint64_t, 256> make_spread_table() {
  std::array<uint64_t, 256> table{};
  for (int v = 0; v < 256; ++v)
    for (int j = 0; j < 8; ++j)
      if ((v >> j) & 1) table[v] |= uint64_t{1} << (8 * j);
  return table;
}
constexpr std::array<uint64_t, 256> kSpread = make_spread_table();

// Counts set bits per position. Byte lanes of `packed_` overflow at 256, so they are flushed
// into 32-bit totals every 255 rows.
class BitVoteCounter {
 public:
  void add(const uint8_t* row) {
    for (int b = 0; b < kDescriptorBytes; ++b) packed_[b] += kSpread[row[b]];
    ++rows_;
    if (++pending_ == 255) flush();
  }
  uint32_t rows() const { return rows_; }
  void majority(uint8_t* out) {
    flush();
    for (int b = 0; b < kDescriptorBytes; ++b) {
      uint8_t byte = 0;
      for (int j = 0; j < 8; ++j)
        if (2 * totals_[b * 8 + j] > rows_) byte |= static_cast<uint8_t>(1u << j);
      out[b] = byte;
    }
  }

 private:
  void flush() {
    for (int b = 0; b < kDescriptorBytes; ++b) {
      for (int j = 0; j < 8; ++j) totals_[b * 8 + j] += (packed_[b] >> (8 * j)) & 0xFF;
      packed_[b] = 0;
    }
    pending_ = 0;
  }
  std::array<uint64_t, kDescriptorBytes> packed_{};
  std::array<uint32_t, kDescriptorBytes * 8> totals_{};
  uint32_t pending_ = 0;
  uint32_t rows_ = 0;
};

const uint8_t* row_at(const uint8_t* rows, size_t i) { return rows + i * kDescriptorBytes; }

// Lowers closest_sq[i] to the squared distance to `seed` where that is closer; returns the sum.
EDGE_SLAM_POPCNT_CLONES
uint64_t update_closest_squared(const uint8_t* rows, size_t n, const uint8_t* seed, std::vector<uint32_t>& closest_sq) {
  uint64_t total = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t d = static_cast<uint32_t>(descriptor_distance(row_at(rows, i), seed));
    if (d * d < closest_sq[i]) closest_sq[i] = d * d;
    total += closest_sq[i];
  }
  return total;
}

// k-means++: each next seed is drawn with probability proportional to its squared distance to
// the closest seed so far. Stops early when every row coincides with a seed.
std::vector<size_t> seed_kmeanspp(const uint8_t* rows, size_t n, int k, std::mt19937_64& rng) {
  std::vector<size_t> seeds{static_cast<size_t>(rng() % n)};
  std::vector<uint32_t> closest_sq(n, std::numeric_limits<uint32_t>::max());
  uint64_t total = update_closest_squared(rows, n, row_at(rows, seeds[0]), closest_sq);
  while (seeds.size() < static_cast<size_t>(k) && total > 0) {
    uint64_t target = rng() % total;
    size_t pick = 0;
    while (target >= closest_sq[pick]) target -= closest_sq[pick++];
    seeds.push_back(pick);
    total = update_closest_squared(rows, n, row_at(rows, pick), closest_sq);
  }
  return seeds;
}

// Assigns every row to its nearest centroid (first one on ties); returns whether any changed.
EDGE_SLAM_POPCNT_CLONES
bool assign_nearest(const uint8_t* rows, size_t n, const std::vector<uint8_t>& centroids, size_t count,
                    std::vector<uint32_t>& assignment) {
  bool changed = false;
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* row = row_at(rows, i);
    uint32_t best = 0;
    int best_d = std::numeric_limits<int>::max();
    for (size_t c = 0; c < count; ++c) {
      const int d = descriptor_distance(row, centroids.data() + c * kDescriptorBytes);
      if (d < best_d) {
        best_d = d;
        best = static_cast<uint32_t>(c);
      }
    }
    changed |= best != assignment[i];
    assignment[i] = best;
  }
  return changed;
}

}  // namespace

size_t BinaryClusters::cluster_count() const { return centroids.size() / kDescriptorBytes; }

void bitwise_majority(const uint8_t* rows, size_t n, uint8_t* out) {
  BitVoteCounter counter;
  for (size_t i = 0; i < n; ++i) counter.add(row_at(rows, i));
  counter.majority(out);
}

BinaryClusters cluster_binary_descriptors(const uint8_t* rows, size_t n, int k, int max_iterations,
                                          std::mt19937_64& rng) {
  BinaryClusters result;
  if (n == 0 || k < 1) return result;
  const std::vector<size_t> seeds = seed_kmeanspp(rows, n, k, rng);
  const size_t count = seeds.size();
  std::vector<uint8_t> centroids(count * kDescriptorBytes);
  for (size_t c = 0; c < count; ++c)
    std::memcpy(&centroids[c * kDescriptorBytes], row_at(rows, seeds[c]), kDescriptorBytes);

  std::vector<uint32_t> assignment(n, std::numeric_limits<uint32_t>::max());
  std::vector<BitVoteCounter> votes(count);
  for (int iteration = 0;; ++iteration) {
    const bool changed = assign_nearest(rows, n, centroids, count, assignment);
    if (!changed || iteration + 1 >= max_iterations) break;
    std::fill(votes.begin(), votes.end(), BitVoteCounter());
    for (size_t i = 0; i < n; ++i) votes[assignment[i]].add(row_at(rows, i));
    for (size_t c = 0; c < count; ++c)  // an emptied cluster keeps its centroid and may refill
      if (votes[c].rows() > 0) votes[c].majority(&centroids[c * kDescriptorBytes]);
  }

  // Drop empty clusters and renumber the rest densely.
  std::vector<uint32_t> members(count, 0);
  for (uint32_t c : assignment) ++members[c];
  std::vector<uint32_t> new_index(count);
  for (size_t c = 0; c < count; ++c) {
    if (members[c] == 0) continue;
    new_index[c] = static_cast<uint32_t>(result.cluster_count());
    result.centroids.insert(result.centroids.end(), centroids.begin() + c * kDescriptorBytes,
                            centroids.begin() + (c + 1) * kDescriptorBytes);
  }
  result.assignment = std::move(assignment);
  for (uint32_t& c : result.assignment) c = new_index[c];
  return result;
}

}  // namespace edge_slam
