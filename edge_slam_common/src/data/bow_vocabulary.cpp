// Vocabulary lookup: tree descent, TF-IDF BowVector + direct index, L1 score, and the
// conversion to/from the flat form used by the file formats.
#include "edge_slam/data/bow_vocabulary.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "edge_slam/data/bow_popcount_dispatch.h"
#include "edge_slam/feature/descriptor_distance.h"

namespace edge_slam {

const uint8_t* BowVocabulary::node_descriptor(NodeId n) const {
  if (n >= node_count()) throw std::out_of_range("BowVocabulary: node id " + std::to_string(n) + " out of range");
  return descriptors_.data() + static_cast<size_t>(n) * kDescriptorBytes;
}

EDGE_SLAM_POPCNT_CLONES
NodeId BowVocabulary::descend(const uint8_t* descriptor, int ancestor_depth, NodeId* ancestor) const {
  NodeId node = 0;
  int depth = 0;
  if (ancestor) *ancestor = 0;
  while (node_word_[node] == kNotAWord) {
    const uint32_t end = child_end_[node];
    NodeId best = child_begin_[node];
    int best_distance = descriptor_distance(descriptor, &descriptors_[size_t{best} * kDescriptorBytes]);
    for (NodeId child = best + 1; child < end; ++child) {
      const int d = descriptor_distance(descriptor, &descriptors_[size_t{child} * kDescriptorBytes]);
      if (d < best_distance) {
        best_distance = d;
        best = child;
      }
    }
    node = best;
    ++depth;
    if (ancestor && depth <= ancestor_depth) *ancestor = node;
  }
  return node;
}

void BowVocabulary::check_descriptors(const cv::Mat& descriptors, const char* caller) const {
  if (empty())
    throw std::logic_error(std::string("BowVocabulary::") + caller + ": the vocabulary is empty (train or load it first)");
  if (descriptors.empty()) return;
  if (descriptors.type() != CV_8UC1 || descriptors.cols != kDescriptorBytes)
    throw std::invalid_argument(std::string("BowVocabulary::") + caller + ": descriptors must be N x " +
                                std::to_string(kDescriptorBytes) + " CV_8UC1, got " +
                                std::to_string(descriptors.rows) + " x " + std::to_string(descriptors.cols) +
                                " of OpenCV type " + std::to_string(descriptors.type()));
}

void BowVocabulary::transform(const cv::Mat& descriptors, BowVector& bow, FeatureVector& features,
                              int levels_up) const {
  bow.clear();
  features.clear();
  check_descriptors(descriptors, "transform");
  const int ancestor_depth = levels_ - levels_up;
  double total = 0;
  for (int i = 0; i < descriptors.rows; ++i) {
    NodeId ancestor = 0;
    const WordId word = node_word_[descend(descriptors.ptr<uint8_t>(i), ancestor_depth, &ancestor)];
    const WordValue weight = word_weight_[word];
    if (weight <= 0) continue;  // a word seen in every training image says nothing
    bow[word] += weight;
    total += weight;
    features[ancestor].push_back(static_cast<uint32_t>(i));
  }
  if (total > 0)
    for (auto& entry : bow) entry.second /= total;
}

void BowVocabulary::transform(const cv::Mat& descriptors, BowVector& bow) const {
  bow.clear();
  check_descriptors(descriptors, "transform");
  double total = 0;
  for (int i = 0; i < descriptors.rows; ++i) {
    const WordId word = node_word_[descend(descriptors.ptr<uint8_t>(i), 0, nullptr)];
    const WordValue weight = word_weight_[word];
    if (weight <= 0) continue;
    bow[word] += weight;
    total += weight;
  }
  if (total > 0)
    for (auto& entry : bow) entry.second /= total;
}

WordId BowVocabulary::word_of(const uint8_t* descriptor) const {
  if (empty()) throw std::logic_error("BowVocabulary::word_of: the vocabulary is empty (train or load it first)");
  return node_word_[descend(descriptor, 0, nullptr)];
}

double BowVocabulary::score(const BowVector& a, const BowVector& b) {
  double norm_a = 0, norm_b = 0;
  for (const auto& e : a) norm_a += std::abs(e.second);
  for (const auto& e : b) norm_b += std::abs(e.second);
  if (norm_a <= 0 || norm_b <= 0) return 0;
  // |a - b|_1 = 2 + sum over shared words of (|ai - bi| - |ai| - |bi|) for unit vectors,
  // so only the shared words need visiting.
  double shared = 0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) {
      ++ia;
    } else if (ib->first < ia->first) {
      ++ib;
    } else {
      const double va = ia->second / norm_a, vb = ib->second / norm_b;
      shared += std::abs(va - vb) - std::abs(va) - std::abs(vb);
      ++ia;
      ++ib;
    }
  }
  const double s = -0.5 * shared;
  return s < 0 ? 0 : (s > 1 ? 1 : s);
}

BowTreeArrays BowVocabulary::to_arrays() const {
  BowTreeArrays tree;
  tree.branching = branching_;
  tree.levels = levels_;
  tree.parents = parents_;
  tree.descriptors = descriptors_;
  tree.weights.assign(node_count(), 0.0);
  tree.is_leaf.assign(node_count(), 0);
  for (WordId w = 0; w < word_node_.size(); ++w) {
    tree.weights[word_node_[w]] = word_weight_[w];
    tree.is_leaf[word_node_[w]] = 1;
  }
  return tree;
}

namespace {

// Children of each node (CSR over the given numbering, children in index order).
struct ChildLists {
  std::vector<uint32_t> begin;  // node_count + 1 offsets into `nodes`
  std::vector<uint32_t> nodes;
  uint32_t count(size_t n) const { return begin[n + 1] - begin[n]; }
};

ChildLists child_lists(const std::vector<uint32_t>& parents) {
  const size_t n = parents.size();
  ChildLists lists;
  lists.begin.assign(n + 1, 0);
  for (size_t i = 1; i < n; ++i) ++lists.begin[parents[i] + 1];
  for (size_t i = 0; i < n; ++i) lists.begin[i + 1] += lists.begin[i];
  lists.nodes.resize(n - 1);
  std::vector<uint32_t> fill(lists.begin.begin(), lists.begin.end() - 1);
  for (size_t i = 1; i < n; ++i) lists.nodes[fill[parents[i]]++] = static_cast<uint32_t>(i);
  return lists;
}

bool children_are_consecutive(const ChildLists& lists) {
  for (size_t node = 0; node + 1 < lists.begin.size(); ++node)
    for (uint32_t c = lists.begin[node] + 1; c < lists.begin[node + 1]; ++c)
      if (lists.nodes[c] != lists.nodes[c - 1] + 1) return false;
  return true;
}

// order[new id] = given id: breadth-first, which makes every node's children consecutive.
std::vector<uint32_t> breadth_first_order(const ChildLists& lists) {
  std::vector<uint32_t> order{0};
  order.reserve(lists.begin.size() - 1);
  for (size_t head = 0; head < order.size(); ++head) {
    const uint32_t node = order[head];
    order.insert(order.end(), lists.nodes.begin() + lists.begin[node], lists.nodes.begin() + lists.begin[node + 1]);
  }
  return order;
}

}  // namespace

BowVocabulary BowVocabulary::from_arrays(const BowTreeArrays& tree) {
  validate_bow_tree(tree);
  const size_t n = tree.node_count();
  ChildLists given = child_lists(tree.parents);
  std::vector<uint32_t> order(n);  // order[internal id] = given id
  for (size_t i = 0; i < n; ++i) order[i] = static_cast<uint32_t>(i);
  std::vector<uint32_t> internal_id = order;  // inverse of order
  if (!children_are_consecutive(given)) {
    order = breadth_first_order(given);
    for (size_t i = 0; i < n; ++i) internal_id[order[i]] = static_cast<uint32_t>(i);
  }

  BowVocabulary voc;
  voc.branching_ = tree.branching;
  voc.levels_ = tree.levels;
  voc.parents_.resize(n);
  voc.child_begin_.resize(n);
  voc.child_end_.resize(n);
  voc.descriptors_.resize(n * kDescriptorBytes);
  voc.node_word_.assign(n, kNotAWord);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t old = order[i];
    voc.parents_[i] = old == 0 ? BowTreeArrays::kNoParent : internal_id[tree.parents[old]];
    const uint32_t children = given.count(old);
    voc.child_begin_[i] = children ? internal_id[given.nodes[given.begin[old]]] : 0;
    voc.child_end_[i] = voc.child_begin_[i] + children;
    std::copy_n(&tree.descriptors[size_t{old} * kDescriptorBytes], kDescriptorBytes,
                &voc.descriptors_[i * kDescriptorBytes]);
    if (tree.is_leaf[old]) {
      voc.node_word_[i] = static_cast<WordId>(voc.word_node_.size());
      voc.word_node_.push_back(static_cast<NodeId>(i));
      voc.word_weight_.push_back(tree.weights[old]);
    }
  }
  return voc;
}

}  // namespace edge_slam
