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
  bool supported = false;    // false: this allocator does not report (every figure 0)
  const char* allocator = "none";  // whose figures these are: "glibc" or "jemalloc"
  size_t in_use_bytes = 0;   // handed out by malloc and not freed yet (small and large blocks)
  size_t kept_free_bytes = 0;  // free memory the allocator keeps (glibc: free chunks, resident or
                               // not; jemalloc: resident pages beyond the live blocks)
  size_t arena_bytes = 0;    // glibc: the arenas' size, in use (small blocks) + kept free;
                             // jemalloc: its resident pages (data, metadata, freed pages not yet returned)
  size_t mapped_bytes = 0;   // glibc: large blocks, each its own mapping (part of in_use_bytes); jemalloc: 0
};

// The allocator that serves the process: jemalloc when it is loaded (preloaded by the launch
// files' allocator:=jemalloc), else glibc's malloc (util/jemalloc_control.h finds out at run time).
// glibc: mallinfo2() over every arena; it walks the arenas' free lists (tens of microseconds),
// so call it at a slow cadence, not per frame. jemalloc: its "stats." counters after an epoch.
HeapUsage read_heap_usage();

// "glibc" or "jemalloc" (or "unknown"): for the nodes' start-up log line.
const char* heap_allocator_name();

}  // namespace edge_slam
