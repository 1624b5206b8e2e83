// Reading and writing vocabulary files. Files are read with a single read into memory and
// parsed from the buffer; all per-node data goes straight into flat vectors.
#include "edge_slam/io/vocabulary_io.h"

#include <charconv>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "edge_slam/feature/descriptor_distance.h"
#include "edge_slam/io/file_bytes.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the binary vocabulary format is little-endian");

namespace edge_slam {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'B', 'O', 'W', 'V', 'O', 'C'};
constexpr uint32_t kVersion = 1;
// magic, version, k, L, node count, checksum
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 4 + 4 + 8;
constexpr size_t kChecksumOffset = 24;
constexpr size_t kBytesPerNode = 4 + kDescriptorBytes + 8 + 1;  // parent, descriptor, weight, leaf flag
constexpr int kTextColumns = 2 + kDescriptorBytes + 1;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("vocabulary file '" + path + "': " + what);
}

// FNV-1a (64 bit): cheap, and catches truncation-free corruption such as flipped bytes.
uint64_t fnv1a(const uint8_t* data, size_t size, uint64_t hash = 0xcbf29ce484222325ull) {
  for (size_t i = 0; i < size; ++i) {
    hash ^= data[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

// Covers the header fields after the magic (except the checksum itself) and the payload.
uint64_t binary_checksum(const std::vector<uint8_t>& file) {
  const uint64_t header_hash = fnv1a(file.data() + sizeof(kMagic), kChecksumOffset - sizeof(kMagic));
  return fnv1a(file.data() + kHeaderBytes, file.size() - kHeaderBytes, header_hash);
}

void write_whole_file(const std::string& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) fail(path, "cannot open for writing");
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) fail(path, "write error (disk full?)");
}

template <typename T>
void put(std::vector<uint8_t>& out, size_t& at, const T& value) {
  std::memcpy(out.data() + at, &value, sizeof(T));
  at += sizeof(T);
}

template <typename T>
T get(const std::vector<uint8_t>& in, size_t& at) {
  T value;
  std::memcpy(&value, in.data() + at, sizeof(T));
  at += sizeof(T);
  return value;
}

BowTreeArrays parse_binary(const std::vector<uint8_t>& file, const std::string& path) {
  if (file.size() < kHeaderBytes)
    fail(path, "truncated: " + std::to_string(file.size()) + " bytes, shorter than the " +
                   std::to_string(kHeaderBytes) + "-byte header");
  size_t at = sizeof(kMagic);
  const uint32_t version = get<uint32_t>(file, at);
  if (version != kVersion)
    fail(path, "unsupported binary vocabulary version " + std::to_string(version) + " (expected " +
                   std::to_string(kVersion) + ")");
  BowTreeArrays tree;
  tree.branching = static_cast<int>(get<uint32_t>(file, at));
  tree.levels = static_cast<int>(get<uint32_t>(file, at));
  const uint64_t nodes = get<uint32_t>(file, at);
  const uint64_t stored_checksum = get<uint64_t>(file, at);
  const uint64_t expected_size = kHeaderBytes + nodes * kBytesPerNode;
  if (file.size() != expected_size)
    fail(path, (file.size() < expected_size ? "truncated: " : "trailing data: ") + std::to_string(file.size()) +
                   " bytes, expected " + std::to_string(expected_size) + " for " + std::to_string(nodes) + " nodes");
  if (binary_checksum(file) != stored_checksum) fail(path, "checksum mismatch (the file is corrupt)");
  // Also keeps the copies below away from empty vectors (memcpy from/to null is undefined).
  if (nodes < 2) fail(path, "holds " + std::to_string(nodes) + " nodes (a tree needs a root and at least one leaf)");

  tree.parents.resize(nodes);
  tree.descriptors.resize(nodes * kDescriptorBytes);
  tree.weights.resize(nodes);
  tree.is_leaf.resize(nodes);
  const uint8_t* payload = file.data() + kHeaderBytes;
  std::memcpy(tree.parents.data(), payload, nodes * 4);
  payload += nodes * 4;
  std::memcpy(tree.descriptors.data(), payload, nodes * kDescriptorBytes);
  payload += nodes * kDescriptorBytes;
  std::memcpy(tree.weights.data(), payload, nodes * 8);
  payload += nodes * 8;
  std::memcpy(tree.is_leaf.data(), payload, nodes);
  return tree;
}

// Whitespace-separated tokens of one line.
class LineTokens {
 public:
  LineTokens(const char* begin, const char* end) : at_(begin), end_(end) {}
  bool next(const char*& token_begin, const char*& token_end) {
    while (at_ < end_ && is_space(*at_)) ++at_;
    if (at_ == end_) return false;
    token_begin = at_;
    while (at_ < end_ && !is_space(*at_)) ++at_;
    token_end = at_;
    return true;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }
  const char* at_;
  const char* end_;
};

template <typename T>
bool parse_number(const char* begin, const char* end, T& value) {
  const auto result = std::from_chars(begin, end, value);
  return result.ec == std::errc() && result.ptr == end;
}

std::string line_context(size_t line_number) { return "line " + std::to_string(line_number) + ": "; }

BowTreeArrays parse_text(const std::vector<uint8_t>& file, const std::string& path) {
  const char* at = reinterpret_cast<const char*>(file.data());
  const char* const end = at + file.size();
  size_t line_number = 0;
  BowTreeArrays tree;
  bool have_header = false;
  const char* tok_begin;
  const char* tok_end;

  while (at < end) {
    const char* line_end = static_cast<const char*>(std::memchr(at, '\n', static_cast<size_t>(end - at)));
    if (!line_end) line_end = end;
    ++line_number;
    LineTokens tokens(at, line_end);
    at = line_end + (line_end < end ? 1 : 0);

    if (!have_header) {
      int header[4];
      int count = 0;
      while (tokens.next(tok_begin, tok_end)) {
        if (count == 4 || !parse_number(tok_begin, tok_end, header[count]))
          fail(path, line_context(line_number) + "expected the header 'k L scoring weighting' (4 integers, e.g. '10 6 0 0')");
        ++count;
      }
      if (count == 0) continue;  // tolerate leading blank lines
      if (count != 4)
        fail(path, line_context(line_number) + "expected the header 'k L scoring weighting' (4 integers), found " +
                       std::to_string(count) + " values");
      if (header[2] != 0)
        fail(path, "unsupported scoring type " + std::to_string(header[2]) + " (only 0 = L1 norm is supported)");
      if (header[3] != 0)
        fail(path, "unsupported weighting type " + std::to_string(header[3]) + " (only 0 = TF-IDF is supported)");
      tree.branching = header[0];
      tree.levels = header[1];
      // The root is implicit in the file.
      tree.parents.push_back(BowTreeArrays::kNoParent);
      tree.descriptors.assign(kDescriptorBytes, 0);
      tree.weights.push_back(0.0);
      tree.is_leaf.push_back(0);
      // Rough reservation (ORBvoc.txt lines are ~100 bytes) avoids repeated regrowth.
      const size_t estimate = file.size() / 80;
      tree.parents.reserve(estimate);
      tree.descriptors.reserve(estimate * kDescriptorBytes);
      tree.weights.reserve(estimate);
      tree.is_leaf.reserve(estimate);
      have_header = true;
      continue;
    }

    int column = 0;
    uint8_t descriptor[kDescriptorBytes];
    uint32_t parent = 0;
    unsigned leaf = 0;
    double weight = 0;
    while (tokens.next(tok_begin, tok_end)) {
      bool ok = true;
      if (column == 0) {
        ok = parse_number(tok_begin, tok_end, parent);
      } else if (column == 1) {
        ok = parse_number(tok_begin, tok_end, leaf) && leaf <= 1;
      } else if (column < 2 + kDescriptorBytes) {
        unsigned byte = 0;
        ok = parse_number(tok_begin, tok_end, byte) && byte <= 255;
        descriptor[column - 2] = static_cast<uint8_t>(byte);
      } else if (column == 2 + kDescriptorBytes) {
        ok = parse_number(tok_begin, tok_end, weight);
      }
      if (!ok)
        fail(path, line_context(line_number) + "column " + std::to_string(column + 1) + " '" +
                       std::string(tok_begin, tok_end) + "' is not a valid " +
                       (column == 0 ? "parent id" : column == 1 ? "leaf flag (0 or 1)"
                                                 : column < 2 + kDescriptorBytes ? "descriptor byte (0-255)"
                                                                                 : "weight"));
      ++column;
    }
    if (column == 0) continue;  // blank line (e.g. at the end of the file)
    if (column != kTextColumns)
      fail(path, line_context(line_number) + "expected " + std::to_string(kTextColumns) +
                     " columns (parent_id is_leaf d0..d31 weight), found " + std::to_string(column));
    tree.parents.push_back(parent);
    tree.descriptors.insert(tree.descriptors.end(), descriptor, descriptor + kDescriptorBytes);
    tree.weights.push_back(weight);
    tree.is_leaf.push_back(static_cast<uint8_t>(leaf));
  }
  if (!have_header) fail(path, "empty file (expected a vocabulary)");
  return tree;
}

bool starts_with_magic(const std::vector<uint8_t>& file) {
  return file.size() >= sizeof(kMagic) && std::memcmp(file.data(), kMagic, sizeof(kMagic)) == 0;
}

bool looks_like_text_vocabulary(const std::vector<uint8_t>& file) {
  for (uint8_t c : file) {
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    return c >= '0' && c <= '9';
  }
  return true;  // empty or blank: the text parser reports it
}

BowTreeArrays parse_any(const std::vector<uint8_t>& file, const std::string& path) {
  if (starts_with_magic(file)) return parse_binary(file, path);
  if (file.size() >= 2 && file[0] == 0x1f && file[1] == 0x8b)
    fail(path, "is gzip-compressed; extract it first (e.g. tar -xzf ORBvoc.txt.tar.gz)");
  if (!looks_like_text_vocabulary(file))
    fail(path, "unknown format: expected the binary vocabulary magic 'ESBOWVOC' or an ORB-SLAM2 text "
               "vocabulary starting with 'k L scoring weighting'");
  return parse_text(file, path);
}

}  // namespace

void save_vocabulary_binary(const BowVocabulary& vocabulary, const std::string& path) {
  if (vocabulary.empty()) fail(path, "refusing to save an empty vocabulary");
  const BowTreeArrays tree = vocabulary.to_arrays();
  const size_t nodes = tree.node_count();
  std::vector<uint8_t> file(kHeaderBytes + nodes * kBytesPerNode);
  size_t at = 0;
  std::memcpy(file.data(), kMagic, sizeof(kMagic));
  at += sizeof(kMagic);
  put(file, at, kVersion);
  put(file, at, static_cast<uint32_t>(tree.branching));
  put(file, at, static_cast<uint32_t>(tree.levels));
  put(file, at, static_cast<uint32_t>(nodes));
  at += 8;  // checksum, filled in below
  std::memcpy(file.data() + at, tree.parents.data(), nodes * 4);
  at += nodes * 4;
  std::memcpy(file.data() + at, tree.descriptors.data(), nodes * kDescriptorBytes);
  at += nodes * kDescriptorBytes;
  std::memcpy(file.data() + at, tree.weights.data(), nodes * 8);
  at += nodes * 8;
  std::memcpy(file.data() + at, tree.is_leaf.data(), nodes);
  at = kChecksumOffset;
  put(file, at, binary_checksum(file));
  write_whole_file(path, file.data(), file.size());
}

void save_vocabulary_text(const BowVocabulary& vocabulary, const std::string& path) {
  if (vocabulary.empty()) fail(path, "refusing to save an empty vocabulary");
  const BowTreeArrays tree = vocabulary.to_arrays();
  std::string text = std::to_string(tree.branching) + " " + std::to_string(tree.levels) + " 0 0\n";
  text.reserve(tree.node_count() * 110);
  char number[64];
  for (size_t i = 1; i < tree.node_count(); ++i) {
    text += std::to_string(tree.parents[i]);
    text += tree.is_leaf[i] ? " 1" : " 0";
    for (int b = 0; b < kDescriptorBytes; ++b) {
      text += ' ';
      text += std::to_string(tree.descriptors[i * kDescriptorBytes + b]);
    }
    // Shortest representation that reads back to the identical double.
    const auto result = std::to_chars(number, number + sizeof(number), tree.weights[i]);
    text += ' ';
    text.append(number, result.ptr);
    text += '\n';
  }
  write_whole_file(path, text.data(), text.size());
}

BowVocabulary load_vocabulary(const std::string& path) {
  const std::vector<uint8_t> file = read_file_bytes(path, "vocabulary");
  return load_vocabulary_from_bytes(file.data(), file.size(), path);
}

BowVocabulary load_vocabulary_from_bytes(const uint8_t* data, size_t size, const std::string& origin) {
  const std::vector<uint8_t> file(data, data + size);
  BowTreeArrays tree = parse_any(file, origin);
  try {
    return BowVocabulary::from_arrays(tree);
  } catch (const std::runtime_error& e) {
    fail(origin, e.what());
  }
}

}  // namespace edge_slam
