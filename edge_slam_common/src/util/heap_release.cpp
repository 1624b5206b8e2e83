#include "edge_slam/util/heap_release.h"

#include <chrono>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "jemalloc_control.h"

namespace edge_slam {

HeapRelease release_free_heap_pages() {
  HeapRelease r;
  const auto start = std::chrono::steady_clock::now();
  if (const auto mallctl = util_detail::jemalloc_mallctl()) {
    // "arena.<MALLCTL_ARENAS_ALL>.purge" (4096 = MALLCTL_ARENAS_ALL): every arena's unused dirty
    // pages go back now instead of after jemalloc's decay time (10 s by default).
    r.supported = true;
    r.released = mallctl("arena.4096.purge", nullptr, nullptr, nullptr, 0) == 0;
  } else {
#if defined(__GLIBC__)
    r.supported = true;
    r.released = malloc_trim(0) != 0;
#endif
  }
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace edge_slam
