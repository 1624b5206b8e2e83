// Writes the fuzzers' seed corpora: valid messages and files made in code (never from a
// recorded dataset), serialized as the receivers get them.
//   make_seeds <corpus root>   ->  <root>/<target>/seed_<n>
#include <edge_slam/data/map.h>
#include <edge_slam/io/map_file.h>
#include <edge_slam/io/map_records.h>
#include <edge_slam/io/map_snapshot.h>
#include <edge_slam/io/vocabulary_io.h>
#include <ros/serialization.h>
#include <sys/stat.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>

#include "fuzz_support.h"

using namespace edge_slam;

namespace {

void write(const std::string& dir, int n, const uint8_t* data, size_t size) {
  ::mkdir(dir.c_str(), 0755);
  std::ofstream(dir + "/seed_" + std::to_string(n), std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

template <class Msg>
void write_message(const std::string& dir, int n, const Msg& msg) {
  const std::vector<uint8_t> bytes = fixtures::serialized(msg);
  write(dir, n, bytes.data(), bytes.size());
}

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_seeds <corpus root>\n";
    return 1;
  }
  const std::string root = argv[1];
  ::mkdir(root.c_str(), 0755);
  int n = 0;
  for (auto [features, obs, fresh] : {std::array<size_t, 3>{0, 0, 0}, {5, 2, 2}, {40, 10, 8}, {200, 80, 40}})
    write_message(root + "/keyframe_message", n++, to_message(fixtures::keyframe(3, features, obs, fresh)));
  n = 0;
  for (size_t features : {0, 3, 60, 300}) write_message(root + "/frame_message", n++, to_message(fixtures::frame(features)));
  n = 0;
  for (auto [kfs, features, points] : {std::array<size_t, 3>{0, 0, 0}, {1, 6, 3}, {3, 20, 10}, {6, 60, 40}}) {
    const MapUpdateRecord u = fixtures::map_update(static_cast<uint32_t>(kfs), features, points);
    write_message(root + "/map_update_message", n++, to_message(u));
    Map map;
    rebuild_from_update(map, u, fuzz::camera(), fuzz::pyramid(), nullptr);
    const std::vector<uint8_t> file = encode_map_file(snapshot_map(map));
    write(root + "/map_file", n - 1, file.data(), file.size());
  }
  const std::string tmp = root + "/.vocabulary.tmp";
  save_vocabulary_binary(*fuzz::vocabulary(), tmp);
  const std::vector<uint8_t> binary = file_bytes(tmp);
  write(root + "/vocabulary_binary", 0, binary.data() + 8, binary.size() - 8);  // the harness adds the magic
  save_vocabulary_text(*fuzz::vocabulary(), tmp);
  const std::vector<uint8_t> text = file_bytes(tmp);
  write(root + "/vocabulary_text", 0, text.data(), text.size());
  std::remove(tmp.c_str());
  std::cout << "seed corpora written under " << root << "\n";
  return 0;
}
