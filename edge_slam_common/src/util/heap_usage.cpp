#include "edge_slam/util/heap_usage.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace edge_slam {

HeapUsage read_heap_usage() {
  HeapUsage h;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 mi = mallinfo2();
  h.supported = true;
  h.mapped_bytes = mi.hblkhd;
  h.in_use_bytes = mi.uordblks + mi.hblkhd;
  h.kept_free_bytes = mi.fordblks;
  h.arena_bytes = mi.arena;
#endif
  return h;
}

}  // namespace edge_slam
