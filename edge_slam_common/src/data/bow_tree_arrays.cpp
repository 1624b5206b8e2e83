// Consistency checks of a vocabulary tree in flat form, so that a corrupt or hand-edited file
// is rejected with a precise reason instead of producing a garbage vocabulary.
#include "edge_slam/data/bow_tree_arrays.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "edge_slam/feature/descriptor_distance.h"

namespace edge_slam {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error("inconsistent vocabulary tree: " + what);
}

}  // namespace

void validate_bow_tree(const BowTreeArrays& tree) {
  if (tree.branching < 2) fail("branching factor k = " + std::to_string(tree.branching) + " (need >= 2)");
  if (tree.levels < 1) fail("depth L = " + std::to_string(tree.levels) + " (need >= 1)");
  const size_t n = tree.node_count();
  if (n < 2) fail("no words (a tree needs a root and at least one leaf)");
  if (n >= BowTreeArrays::kNoParent) fail("too many nodes (" + std::to_string(n) + ")");
  if (tree.descriptors.size() != n * kDescriptorBytes)
    fail("descriptor array holds " + std::to_string(tree.descriptors.size()) + " bytes, expected " +
         std::to_string(n * kDescriptorBytes) + " for " + std::to_string(n) + " nodes");
  if (tree.weights.size() != n)
    fail("weight array has " + std::to_string(tree.weights.size()) + " entries, expected " + std::to_string(n));
  if (tree.is_leaf.size() != n)
    fail("leaf flag array has " + std::to_string(tree.is_leaf.size()) + " entries, expected " + std::to_string(n));
  if (tree.parents[0] != BowTreeArrays::kNoParent) fail("node 0 (the root) has a parent");

  std::vector<uint32_t> child_count(n, 0);
  std::vector<int> depth(n, 0);
  for (size_t i = 1; i < n; ++i) {
    const uint32_t p = tree.parents[i];
    if (p >= i)
      fail("node " + std::to_string(i) + " has parent " + std::to_string(p) +
           ", which is not an earlier node");
    if (++child_count[p] > static_cast<uint32_t>(tree.branching))
      fail("node " + std::to_string(p) + " has more than k = " + std::to_string(tree.branching) + " children");
    depth[i] = depth[p] + 1;
    if (depth[i] > tree.levels)
      fail("node " + std::to_string(i) + " is deeper than L = " + std::to_string(tree.levels));
  }
  for (size_t i = 0; i < n; ++i) {
    const uint8_t flag = tree.is_leaf[i];
    if (flag > 1) fail("node " + std::to_string(i) + " has leaf flag " + std::to_string(flag) + " (expected 0 or 1)");
    if ((flag == 1) != (child_count[i] == 0))
      fail("node " + std::to_string(i) + (flag ? " is flagged a leaf but has children"
                                               : " is flagged inner but has no children"));
    if (flag && !(std::isfinite(tree.weights[i]) && tree.weights[i] >= 0))
      fail("word node " + std::to_string(i) + " has weight " + std::to_string(tree.weights[i]) +
           " (expected a finite value >= 0)");
  }
}

}  // namespace edge_slam
