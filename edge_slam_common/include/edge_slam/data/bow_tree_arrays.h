// The vocabulary tree as plain parallel arrays, one entry per node, root first.
// This is the exchange form between the vocabulary and its file formats: loaders fill it,
// BowVocabulary::from_arrays validates it and builds the search structure from it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "edge_slam/data/bow_types.h"

namespace edge_slam {

struct BowTreeArrays {
  static constexpr uint32_t kNoParent = 0xFFFFFFFFu;  // parent of the root

  int branching = 0;              // k: maximum children per node
  int levels = 0;                 // L: maximum depth of a leaf (root is depth 0)
  std::vector<uint32_t> parents;  // parents[0] == kNoParent; parents[i] < i for i > 0
  std::vector<uint8_t> descriptors;  // node_count() * kDescriptorBytes, row-major
  std::vector<WordValue> weights;    // idf of leaves; ignored for inner nodes
  std::vector<uint8_t> is_leaf;      // 1 for words (nodes without children), else 0

  size_t node_count() const { return parents.size(); }
};

// Throws std::runtime_error describing the first inconsistency: array sizes, parent order,
// leaf flags disagreeing with the children, more than k children, leaves deeper than L,
// non-finite or negative weights.
void validate_bow_tree(const BowTreeArrays& tree);

}  // namespace edge_slam
