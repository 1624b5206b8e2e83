#include "jemalloc_control.h"

#include <dlfcn.h>

namespace edge_slam {
namespace util_detail {

MallctlFunction jemalloc_mallctl() {
  // RTLD_DEFAULT finds the symbol only when jemalloc is loaded (preloaded or linked by the host
  // program); with glibc's malloc alone there is no mallctl and the readings stay glibc's.
  static const MallctlFunction fn = reinterpret_cast<MallctlFunction>(dlsym(RTLD_DEFAULT, "mallctl"));
  return fn;
}

}  // namespace util_detail
}  // namespace edge_slam
