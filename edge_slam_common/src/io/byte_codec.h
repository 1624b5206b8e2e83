// Little-endian byte writer / bounds-checked reader for our binary files. The reader never
// reads past its buffer and never allocates more elements than the remaining bytes could
// hold, so a corrupt length field yields an error, not a huge allocation.
#pragma once
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "our binary files are little-endian");

namespace edge_slam {

class ByteWriter {
 public:
  template <typename T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const uint8_t*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void put_bytes(const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + size);
  }
  void put_string(const std::string& s) {
    put(static_cast<uint32_t>(s.size()));
    put_bytes(s.data(), s.size());
  }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : at_(data), end_(data + size), begin_(data) {}

  template <typename T>
  T get(const char* field) {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T), field), sizeof(T));
    return value;
  }
  const uint8_t* take(size_t size, const char* field) {
    if (size > static_cast<size_t>(end_ - at_))
      throw std::runtime_error(std::string("truncated at byte ") + std::to_string(at_ - begin_) + " reading " + field);
    const uint8_t* p = at_;
    at_ += size;
    return p;
  }
  // An element count whose elements take at least `min_element_bytes` each.
  size_t count(size_t min_element_bytes, const char* field) {
    const uint32_t n = get<uint32_t>(field);
    if (static_cast<uint64_t>(n) * min_element_bytes > remaining())
      throw std::runtime_error(std::string(field) + " count " + std::to_string(n) + " does not fit the " +
                               std::to_string(remaining()) + " bytes left");
    return n;
  }
  std::string get_string(size_t max_size, const char* field) {
    const size_t n = count(1, field);
    if (n > max_size) throw std::runtime_error(std::string(field) + " longer than " + std::to_string(max_size));
    const uint8_t* p = take(n, field);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  size_t remaining() const { return static_cast<size_t>(end_ - at_); }

 private:
  const uint8_t* at_;
  const uint8_t* end_;
  const uint8_t* begin_;
};

// FNV-1a (64 bit): detects flipped or shifted bytes anywhere in a file.
inline uint64_t fnv1a64(const uint8_t* data, size_t size, uint64_t hash = 0xcbf29ce484222325ull) {
  for (size_t i = 0; i < size; ++i) {
    hash ^= data[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

}  // namespace edge_slam
