// FlatIdSet against std::unordered_set on random and consecutive ids, through growth, clear
// and reuse; kNoId is never stored.
#include <gtest/gtest.h>

#include <random>
#include <unordered_set>

#include "edge_slam/util/flat_id_set.h"

using namespace edge_slam;

TEST(FlatIdSet, AgreesWithUnorderedSet) {
  std::mt19937 rng(3);
  FlatIdSet flat;
  for (int round = 0; round < 3; ++round) {
    std::unordered_set<uint32_t> ref;
    flat.clear();
    // Consecutive ids (mobile), ids near the edge's half of the id space, and random repeats.
    std::uniform_int_distribution<uint32_t> near(0, 30000), edge(kEdgePointIdFirst, kEdgePointIdFirst + 30000);
    for (int i = 0; i < 40000; ++i) {
      const uint32_t id = i % 3 == 0 ? near(rng) : i % 3 == 1 ? edge(rng) : static_cast<uint32_t>(i / 3);
      ASSERT_EQ(flat.insert(id), ref.insert(id).second) << "id " << id;
    }
    ASSERT_EQ(flat.size(), ref.size());
    for (uint32_t id = 0; id < 31000; ++id) ASSERT_EQ(flat.contains(id), ref.count(id) > 0) << id;
    for (uint32_t id : ref) ASSERT_TRUE(flat.contains(id));
    EXPECT_FALSE(flat.contains(kEdgePointIdFirst + 40000));
  }
  flat.clear();
  EXPECT_TRUE(flat.empty());
  EXPECT_FALSE(flat.contains(5));
}

TEST(FlatIdSet, NoIdIsNeverStoredAndEmptySetAnswers) {
  FlatIdSet s;
  EXPECT_FALSE(s.contains(0));
  EXPECT_FALSE(s.insert(kNoId));
  EXPECT_FALSE(s.contains(kNoId));
  EXPECT_TRUE(s.insert(0));
  EXPECT_FALSE(s.insert(0));
  EXPECT_EQ(s.size(), 1u);
  s.reserve(100000);  // growing keeps the content
  EXPECT_TRUE(s.contains(0));
  EXPECT_EQ(s.size(), 1u);
}
