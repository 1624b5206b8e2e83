// A whole file in memory, for the binary formats that are decoded from a buffer (map file,
// vocabulary): one read, and errors that name the kind of file and its path.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace edge_slam {

// Throws std::runtime_error("<kind> file '<path>': <what went wrong>") when the file cannot be
// opened, sized or read.
std::vector<uint8_t> read_file_bytes(const std::string& path, const std::string& kind);

}  // namespace edge_slam
