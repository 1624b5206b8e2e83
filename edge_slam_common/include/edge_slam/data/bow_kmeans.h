// One k-means step of vocabulary training on binary descriptors: k-means++ seeding with
// squared Hamming distances, centroids by per-bit majority vote (k-medians in Hamming space).
#pragma once
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace edge_slam {

struct BinaryClusters {
  std::vector<uint8_t> centroids;   // cluster_count() * kDescriptorBytes
  std::vector<uint32_t> assignment; // per input row: index of its (nearest) centroid
  size_t cluster_count() const;
};

// rows: n contiguous 32-byte descriptors. Returns at most k clusters (fewer when the rows
// have fewer distinct values); clusters that end up empty are dropped. Iterates until no
// assignment changes or max_iterations assignment passes; the returned assignment is always
// nearest-centroid for the returned centroids, so descending the tree retraces it.
BinaryClusters cluster_binary_descriptors(const uint8_t* rows, size_t n, int k, int max_iterations,
                                          std::mt19937_64& rng);

// Per-bit majority of the given rows (ties -> 0), written to out[kDescriptorBytes].
void bitwise_majority(const uint8_t* rows, size_t n, uint8_t* out);

}  // namespace edge_slam
