// Fuzz target: bytes -> the vocabulary loader (ORB-SLAM2 text format, and whatever format the
// bytes claim) -> a loaded vocabulary transforms descriptors.
#include "fuzz_support.h"

using namespace edge_slam;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::load_and_use_vocabulary(data, size);
  return 0;
}
