// Value types of the bag-of-words representation of an image, shared by the vocabulary,
// keyframe database (place recognition) and BoW-guided matching.
#pragma once
#include <cstdint>
#include <map>
#include <vector>

namespace edge_slam {

using WordId = uint32_t;     // index of a leaf of the vocabulary tree
using NodeId = uint32_t;     // index of any node of the vocabulary tree (0 = root)
using WordValue = double;

// Word -> TF-IDF weight, normalised to unit L1 norm.
using BowVector = std::map<WordId, WordValue>;

// Direct index: tree node at a chosen level -> indices of the features that descend through it.
// Matching only compares features that share a node, which is what makes BoW matching fast.
using FeatureVector = std::map<NodeId, std::vector<uint32_t>>;

}  // namespace edge_slam
