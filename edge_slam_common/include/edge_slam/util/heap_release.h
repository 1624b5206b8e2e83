// Giving the heap's free pages back to the operating system.
//
// Each Local-Map update on the mobile builds a new map of ~10^4 points and frees the one it
// replaces. The memory in use stays flat, but glibc keeps the freed chunks in its arenas, where
// the long-lived objects allocated in between fragment them: on the 6-minute long synthetic
// run the mobile's in-use heap stayed at 46-50 MB while its free-but-kept heap grew from 33 to
// 46 MB and RSS rose 1.6 MB/min. malloc_trim(0) returns every whole free page of every arena.
#pragma once

namespace edge_slam {

struct HeapRelease {
  bool supported = false;  // false: this C library cannot give pages back (nothing was done)
  bool released = false;   // some memory went back to the system
  double ms = 0;           // wall time of the call
};

HeapRelease release_free_heap_pages();

}  // namespace edge_slam
