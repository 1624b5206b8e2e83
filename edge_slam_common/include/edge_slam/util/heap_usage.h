// What the C library's allocator holds, as opposed to what the process's RSS shows.
//
// The long-run target bounds the mobile's RSS slope, but RSS mixes three things: the data the
// program keeps (a leak or an ever-growing history shows here), the free chunks the allocator
// keeps in its arenas between Local-Map updates (fragmentation), and pages that are not heap at
// all (code and libraries paged in as new paths run, thread stacks). Reading the allocator's own
// accounting tells the first from the others. With the object counts beside it (instance_count.h)
// it found what grew on the long run: not the Local-Map but the mobile's latched rviz path,
// whose growing serialisation buffers also fragmented the arenas (RSS 0.31-0.93 MB/min before
// the fix, 0.05-1.11 in four runs after, the live heap flat; what is left is the arena keeping
// the largest Local-Map so far; docs/benchmarks/2026-12-07/mobile_path_growth).
#pragma once
#include <cstddef>

namespace edge_slam {

struct HeapUsage {
  bool supported = false;    // false: this C library does not report (every figure 0)
  size_t in_use_bytes = 0;   // handed out by malloc and not freed yet (small and large blocks)
  size_t kept_free_bytes = 0;  // free chunks the arenas keep (resident or not)
  size_t arena_bytes = 0;    // the arenas' size: in use (small blocks) + kept free
  size_t mapped_bytes = 0;   // large blocks, each its own mapping (part of in_use_bytes)
};

// glibc: mallinfo2() over every arena; it walks the arenas' free lists (tens of microseconds),
// so call it at a slow cadence, not per frame.
HeapUsage read_heap_usage();

}  // namespace edge_slam
