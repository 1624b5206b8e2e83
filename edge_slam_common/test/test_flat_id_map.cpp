// FlatIdMap against std::unordered_map under random put / erase / find sequences (erase is
// the delicate part: backward-shift deletion must keep every remaining key reachable), plus
// growth, clear, swap, iteration and the kNoId key.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <unordered_map>

#include "edge_slam/util/flat_id_map.h"

using namespace edge_slam;

TEST(FlatIdMap, AgreesWithUnorderedMapUnderRandomOperations) {
  std::mt19937 rng(8);
  FlatIdMap<int> flat;
  std::unordered_map<uint32_t, int> ref;
  // Small key ranges make long probe runs and many erase-inside-a-run cases.
  for (const uint32_t range : {64u, 1000u, 100000u}) {
    std::uniform_int_distribution<uint32_t> key(0, range - 1);
    for (int step = 0; step < 60000; ++step) {
      const uint32_t k = step % 7 == 0 ? kEdgePointIdFirst + key(rng) : key(rng);
      const int op = static_cast<int>(rng() % 3);
      if (op == 0) {
        flat.put(k, step);
        ref[k] = step;
      } else if (op == 1) {
        ASSERT_EQ(flat.erase(k), ref.erase(k) == 1) << "erase " << k;
      } else {
        const int* v = flat.find(k);
        const auto it = ref.find(k);
        ASSERT_EQ(v != nullptr, it != ref.end()) << "find " << k;
        if (v) ASSERT_EQ(*v, it->second);
      }
      ASSERT_EQ(flat.size(), ref.size());
    }
    // Every key still reachable, and iteration visits exactly the content.
    for (const auto& [k, v] : ref) ASSERT_TRUE(flat.find(k) && *flat.find(k) == v) << k;
    size_t visited = 0;
    flat.for_each([&](uint32_t k, int v) {
      ++visited;
      ASSERT_EQ(ref.at(k), v);
    });
    EXPECT_EQ(visited, ref.size());
  }
}

TEST(FlatIdMap, SharedPointersClearSwapAndNoId) {
  FlatIdMap<std::shared_ptr<int>> a, b;
  auto p = std::make_shared<int>(5);
  a.put(3, p);
  EXPECT_EQ(p.use_count(), 2);
  a.put(kNoId, p);  // not a key: ignored
  EXPECT_EQ(a.size(), 1u);
  EXPECT_EQ(a.find(kNoId), nullptr);
  a.swap(b);
  EXPECT_TRUE(a.empty());
  ASSERT_NE(b.find(3), nullptr);
  EXPECT_EQ(**b.find(3), 5);
  b.erase(3);
  EXPECT_EQ(p.use_count(), 1);  // the erased slot released its value
  b.put(4, p);
  b.clear();
  EXPECT_EQ(p.use_count(), 1);
  EXPECT_EQ(b.find(4), nullptr);
  b.reserve(1000);
  b.put(7, p);
  EXPECT_NE(b.slot_address(7), nullptr);
  EXPECT_EQ(b.find(7)->get(), p.get());
}
