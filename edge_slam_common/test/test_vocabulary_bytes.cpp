// The vocabulary loader on bytes in memory: a binary file with a correct checksum but no
// nodes (found by fuzz_vocabulary_binary: it reached memcpy with a null pointer) and other
// malformed inputs are refused with a reason naming the origin.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "edge_slam/io/vocabulary_io.h"

namespace edge_slam {
namespace {

// A binary vocabulary header for `nodes` nodes and no payload, with the checksum it needs.
std::vector<uint8_t> binary_header(uint32_t nodes) {
  std::vector<uint8_t> file = {'E', 'S', 'B', 'O', 'W', 'V', 'O', 'C'};
  for (uint32_t v : {1u, 3u, 2u, nodes}) file.insert(file.end(), reinterpret_cast<uint8_t*>(&v), reinterpret_cast<uint8_t*>(&v) + 4);
  uint64_t h = 0xcbf29ce484222325ull;
  for (size_t i = 8; i < file.size(); ++i) h = (h ^ file[i]) * 0x100000001b3ull;
  file.insert(file.end(), reinterpret_cast<uint8_t*>(&h), reinterpret_cast<uint8_t*>(&h) + 8);
  return file;
}

std::string error_of(const std::vector<uint8_t>& bytes) {
  try {
    load_vocabulary_from_bytes(bytes.data(), bytes.size(), "memory.bin");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(VocabularyBytes, EmptyBinaryTreeIsRefused) {
  const std::string e = error_of(binary_header(0));
  EXPECT_NE(e.find("memory.bin"), std::string::npos) << e;
  EXPECT_NE(e.find("0 nodes"), std::string::npos) << e;
}

TEST(VocabularyBytes, MalformedInputsAreRefused) {
  EXPECT_NE(error_of({}).find("empty"), std::string::npos);
  EXPECT_NE(error_of({'x', 'y'}).find("unknown format"), std::string::npos);
  EXPECT_NE(error_of(binary_header(1)).find("truncated"), std::string::npos);
  const std::string text = "3 2 0 0\n0 1 " + std::string(31 * 2, ' ') + "\n";
  EXPECT_FALSE(error_of({text.begin(), text.end()}).empty());
}

}  // namespace
}  // namespace edge_slam
