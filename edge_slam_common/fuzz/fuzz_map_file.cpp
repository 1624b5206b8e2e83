// Fuzz target: bytes -> the Global-Map file decoder -> map objects -> a fresh Map and KeyFrame
// database (EdgeSession::load_map without the threads). The harness fixes up the checksum so
// mutations reach the payload parser and the record checks.
#include <edge_slam/io/map_file.h>
#include <edge_slam/io/map_snapshot.h>

#include <cstring>
#include <stdexcept>
#include <vector>

#include "fuzz_support.h"

using namespace edge_slam;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> file(data, data + size);
  if (file.size() >= 32) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 32; i < file.size(); ++i) h = (h ^ file[i]) * 0x100000001b3ull;
    std::memcpy(file.data() + 24, &h, 8);
    const uint64_t payload = file.size() - 32;
    std::memcpy(file.data() + 16, &payload, 8);
  }
  try {
    const MapSnapshot snapshot = decode_map_file(file.data(), file.size(), "fuzz input");
    const MapObjects objects = map_objects_from_snapshot(snapshot, fuzz::camera(), fuzz::pyramid(),
                                                         fuzz::vocabulary().get());
    Map map;
    KeyFrameDatabase database;
    install_snapshot(snapshot, objects, map, database);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
