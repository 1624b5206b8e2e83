#include "edge_slam/util/heap_release.h"

#include <chrono>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace edge_slam {

HeapRelease release_free_heap_pages() {
  HeapRelease r;
#if defined(__GLIBC__)
  const auto start = std::chrono::steady_clock::now();
  r.supported = true;
  r.released = malloc_trim(0) != 0;
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
#endif
  return r;
}

}  // namespace edge_slam
