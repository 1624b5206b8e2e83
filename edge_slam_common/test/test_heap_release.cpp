// release_free_heap_pages gives freed, fragmented heap memory back: the situation of the
// mobile after an update replaced its Local-Map (many small objects freed, long-lived ones
// allocated between them, so the heap's top cannot shrink by itself).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "edge_slam/util/heap_release.h"

namespace edge_slam {
namespace {

double resident_mb() {
  long pages = 0, resident = 0;
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return -1;
  const int n = std::fscanf(f, "%ld %ld", &pages, &resident);
  std::fclose(f);
  return n == 2 ? resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1e6 : -1;
}

TEST(HeapRelease, GivesTheFreedChunksOfAFragmentedHeapBack) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "only glibc can give free heap pages back";
#endif
  constexpr size_t kChunk = 2000, kChunks = 40000;  // 80 MB of map-point-sized objects
  std::vector<std::unique_ptr<char[]>> freed, kept;
  freed.reserve(kChunks);
  kept.reserve(kChunks / 64);
  for (size_t i = 0; i < kChunks; ++i) {
    freed.emplace_back(new char[kChunk]);
    std::memset(freed.back().get(), 1, kChunk);  // resident, not just reserved
    if (i % 64 == 0) {  // a long-lived object every 128 KB: the free space stays in pieces
      kept.emplace_back(new char[64]);
      std::memset(kept.back().get(), 2, 64);
    }
  }
  freed.clear();
  const double before = resident_mb();
  ASSERT_GT(before, 0) << "/proc/self/statm unreadable";
  const HeapRelease r = release_free_heap_pages();
  const double after = resident_mb();
  EXPECT_TRUE(r.supported);
  EXPECT_TRUE(r.released);
  EXPECT_GE(r.ms, 0.0);
  EXPECT_LT(after, before - 40.0) << "resident " << before << " MB before, " << after << " MB after";
  EXPECT_EQ(kept.size(), kChunks / 64);  // they are still alive (and still hold their bytes)
  for (const auto& k : kept) ASSERT_EQ(k[63], 2);
}

}  // namespace
}  // namespace edge_slam
