// read_heap_usage follows what the program holds: blocks allocated show as in use until freed,
// small ones in the arenas, large ones as their own mappings; freed small blocks stay with the
// arenas as kept-free memory.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

#include "edge_slam/util/heap_usage.h"

namespace edge_slam {
namespace {

constexpr size_t kMB = 1u << 20;

TEST(HeapUsage, InUseFollowsSmallAndLargeAllocationsUntilFreed) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "only glibc reports its heap";
#endif
  const HeapUsage before = read_heap_usage();
  ASSERT_TRUE(before.supported);
  ASSERT_GT(before.in_use_bytes, 0u);  // the test runner itself holds memory

  // 20 MB of map-point-sized blocks (arena) and one 16 MiB image-sized block (its own mapping).
  std::vector<std::unique_ptr<char[]>> small;
  for (size_t i = 0; i < 10000; ++i) {
    small.emplace_back(new char[2000]);
    std::memset(small.back().get(), 1, 2000);
  }
  std::unique_ptr<char[]> large(new char[16 * kMB]);
  std::memset(large.get(), 1, 16 * kMB);
  const size_t small_bytes = 10000 * 2000, both = small_bytes + 16 * kMB;
  const HeapUsage held = read_heap_usage();
  EXPECT_GE(held.in_use_bytes, before.in_use_bytes + both);
  // The large block is a mapping unless glibc's dynamic threshold has grown past it: either way
  // what is in use lies in the arenas and the mappings.
  EXPECT_GE(held.arena_bytes + held.mapped_bytes, held.in_use_bytes);
  EXPECT_LE(held.in_use_bytes - held.mapped_bytes, held.arena_bytes);

  small.clear();
  large.reset();
  const HeapUsage after = read_heap_usage();
  EXPECT_LE(after.in_use_bytes, held.in_use_bytes - both);
  EXPECT_GE(after.kept_free_bytes + (held.arena_bytes - after.arena_bytes), small_bytes);  // kept or trimmed
}

}  // namespace
}  // namespace edge_slam
