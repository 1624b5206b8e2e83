#include "edge_slam/util/heap_usage.h"

#include <cstdint>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "jemalloc_control.h"

namespace edge_slam {
namespace {

bool read_jemalloc_usage(util_detail::MallctlFunction mallctl, HeapUsage* h) {
  // jemalloc caches its statistics; writing "epoch" refreshes them.
  uint64_t epoch = 1;
  size_t len = sizeof(epoch);
  if (mallctl("epoch", &epoch, &len, &epoch, len) != 0) return false;
  size_t allocated = 0, resident = 0;
  len = sizeof(size_t);
  if (mallctl("stats.allocated", &allocated, &len, nullptr, 0) != 0) return false;
  len = sizeof(size_t);
  if (mallctl("stats.resident", &resident, &len, nullptr, 0) != 0) return false;
  h->allocator = "jemalloc";
  h->in_use_bytes = allocated;
  // Resident: pages backing live blocks, the allocator's metadata and freed ("dirty") pages not
  // yet given back. jemalloc gives large blocks no mapping of their own (mapped_bytes stays 0).
  h->arena_bytes = resident;
  h->kept_free_bytes = resident > allocated ? resident - allocated : 0;
  h->supported = true;
  return true;
}

}  // namespace

HeapUsage read_heap_usage() {
  HeapUsage h;
  if (const auto mallctl = util_detail::jemalloc_mallctl()) {
    if (read_jemalloc_usage(mallctl, &h)) return h;
    return HeapUsage{};  // jemalloc without statistics: glibc's figures would describe an idle heap
  }
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 mi = mallinfo2();
  h.supported = true;
  h.allocator = "glibc";
  h.mapped_bytes = mi.hblkhd;
  h.in_use_bytes = mi.uordblks + mi.hblkhd;
  h.kept_free_bytes = mi.fordblks;
  h.arena_bytes = mi.arena;
#endif
  return h;
}

const char* heap_allocator_name() {
  if (util_detail::jemalloc_mallctl()) return "jemalloc";
#if defined(__GLIBC__)
  return "glibc";
#else
  return "unknown";
#endif
}

}  // namespace edge_slam
