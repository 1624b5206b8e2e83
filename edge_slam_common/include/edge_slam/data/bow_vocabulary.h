// Hierarchical bag-of-words vocabulary for 256-bit ORB descriptors (DBoW2-like, own code).
// A k-ary tree trained by hierarchical k-means++ with bitwise-majority centroids; the leaves
// are the words, weighted by idf. An image becomes a TF-IDF BowVector plus a direct index
// (FeatureVector) by descending each descriptor to its closest child at every level.
// Const members touch no mutable state: one loaded vocabulary can serve all threads.
#pragma once
#include <opencv2/core.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "edge_slam/data/bow_tree_arrays.h"
#include "edge_slam/data/bow_types.h"

namespace edge_slam {

struct VocabularyParams {
  int branching = 10;   // k
  int levels = 6;       // L
  uint64_t seed = 1;    // k-means++ seeding; same seed + same data -> same vocabulary
  int max_iterations = 10;  // per k-means step; it also stops once assignments are stable
};

class BowVocabulary {
 public:
  // descriptors_per_image: one N x 32 CV_8U matrix per training image (empty allowed).
  // Throws std::invalid_argument on bad parameters, wrong descriptor types or no descriptors.
  void train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyParams& params);

  // descriptors: N x 32 CV_8U. levels_up: the direct index groups features by their ancestor
  // `levels_up` levels above the leaf level L (ORB-SLAM2 uses 4); a leaf shallower than that
  // level is its own group. Features of zero-weight words are left out of both outputs.
  void transform(const cv::Mat& descriptors, BowVector& bow, FeatureVector& features,
                 int levels_up) const;
  void transform(const cv::Mat& descriptors, BowVector& bow) const;
  WordId word_of(const uint8_t* descriptor) const;

  // L1 score 1 - 0.5 * | a/|a| - b/|b| |_1, in [0, 1]; 0 if either vector is empty.
  static double score(const BowVector& a, const BowVector& b);

  size_t size() const { return word_node_.size(); }  // number of words
  bool empty() const { return word_node_.empty(); }
  int branching() const { return branching_; }
  int levels() const { return levels_; }
  WordValue idf(WordId w) const { return word_weight_.at(w); }

  size_t node_count() const { return parents_.size(); }
  NodeId node_of_word(WordId w) const { return word_node_.at(w); }
  const uint8_t* node_descriptor(NodeId n) const;

  // Flat form for file formats. from_arrays validates (std::runtime_error on inconsistency).
  // Node numbering is kept when every node's children are consecutive (as in our files and in
  // DBoW2/ORB-SLAM2 files, so node and word ids match ORB-SLAM2's); otherwise nodes are
  // renumbered breadth-first. Word ids follow node order.
  BowTreeArrays to_arrays() const;
  static BowVocabulary from_arrays(const BowTreeArrays& tree);

 private:
  static constexpr WordId kNotAWord = 0xFFFFFFFFu;

  // Descends to the closest leaf; if ancestor is given, stores the node on the path at
  // ancestor_depth (or the leaf itself if it is shallower).
  NodeId descend(const uint8_t* descriptor, int ancestor_depth, NodeId* ancestor) const;
  void check_descriptors(const cv::Mat& descriptors, const char* caller) const;

  int branching_ = 0;
  int levels_ = 0;
  // Children of node n are the consecutive nodes [child_begin_[n], child_end_[n]).
  std::vector<uint32_t> parents_;
  std::vector<uint32_t> child_begin_;
  std::vector<uint32_t> child_end_;
  std::vector<uint8_t> descriptors_;  // node_count() * 32
  std::vector<WordId> node_word_;     // kNotAWord for inner nodes
  std::vector<NodeId> word_node_;
  std::vector<WordValue> word_weight_;
};

}  // namespace edge_slam
