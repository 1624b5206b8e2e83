#include "edge_slam/io/file_bytes.h"

#include <fstream>
#include <stdexcept>

namespace edge_slam {

std::vector<uint8_t> read_file_bytes(const std::string& path, const std::string& kind) {
  auto fail = [&](const std::string& what) {
    throw std::runtime_error(kind + " file '" + path + "': " + what);
  };
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) fail("cannot open for reading");
  const std::streamoff size = in.tellg();
  if (size < 0) fail("cannot determine the file size");
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) fail("read error");
  return bytes;
}

}  // namespace edge_slam
