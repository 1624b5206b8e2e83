// Fuzz target: the binary vocabulary loader. The input is the file after its 8-byte magic;
// the harness writes the magic and a correct checksum so mutations reach the tree checks
// instead of all stopping at "checksum mismatch" (that check has its own unit test).
#include <cstring>
#include <vector>

#include "fuzz_support.h"

using namespace edge_slam;

namespace {
constexpr size_t kHeader = 32, kChecksumAt = 24;
uint64_t fnv1a(const uint8_t* p, size_t n, uint64_t h) {
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> file = {'E', 'S', 'B', 'O', 'W', 'V', 'O', 'C'};
  file.insert(file.end(), data, data + size);
  if (file.size() >= kHeader) {
    uint64_t h = fnv1a(file.data() + 8, kChecksumAt - 8, 0xcbf29ce484222325ull);
    h = fnv1a(file.data() + kHeader, file.size() - kHeader, h);
    std::memcpy(file.data() + kChecksumAt, &h, 8);
  }
  fuzz::load_and_use_vocabulary(file.data(), file.size());
  return 0;
}
