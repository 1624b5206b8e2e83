// Private to src/util: jemalloc's control interface, when the process runs on jemalloc.
//
// The nodes can run on jemalloc instead of glibc's malloc (launch files, `allocator:=jemalloc`,
// which preloads libjemalloc.so.2 into the nodelet manager). The core does not link jemalloc: it
// looks up `mallctl` at run time, so one build serves both allocators and the heap readings and
// the page release follow whichever allocator actually serves the process.
#pragma once
#include <cstddef>

namespace edge_slam {
namespace util_detail {

using MallctlFunction = int (*)(const char* name, void* oldp, size_t* oldlenp, void* newp, size_t newlen);

// jemalloc's mallctl when jemalloc is the process's allocator, else nullptr (looked up once).
MallctlFunction jemalloc_mallctl();

}  // namespace util_detail
}  // namespace edge_slam
