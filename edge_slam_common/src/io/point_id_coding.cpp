#include "edge_slam/io/point_id_coding.h"

#include <algorithm>

#include "bit_stream.h"
#include "byte_codec.h"

namespace edge_slam {
namespace {

constexpr size_t kHeaderBytes = 1 + 2 * (4 + 1);

struct IdClass {
  uint32_t base = 0, bits = 0;
};

}  // namespace

std::vector<uint8_t> encode_point_ids(const std::vector<uint32_t>& ids) {
  uint32_t low_min = UINT32_MAX, low_max = 0, high_min = UINT32_MAX, high_max = 0;
  for (uint32_t id : ids) {
    if (id < kHighPointIds) {
      low_min = std::min(low_min, id);
      low_max = std::max(low_max, id);
    } else {
      high_min = std::min(high_min, id);
      high_max = std::max(high_max, id);
    }
  }
  IdClass low, high;
  high.base = kHighPointIds;
  if (low_min <= low_max) low = {low_min, bits_for(low_max - low_min)};
  if (high_min <= high_max) high = {high_min, bits_for(high_max - high_min)};

  ByteWriter header;
  header.put(kPointIdCoding);
  for (const IdClass& c : {low, high}) {
    header.put(c.base);
    header.put(static_cast<uint8_t>(c.bits));
  }
  std::vector<uint8_t> out = std::move(header.bytes());
  BitWriter bits(out);
  for (uint32_t id : ids) {
    const bool is_high = id >= kHighPointIds;
    const IdClass& c = is_high ? high : low;
    bits.put_bit(is_high ? 1 : 0);
    bits.put(id - c.base, c.bits);
  }
  return out;
}

bool decode_point_ids(const uint8_t* data, size_t size, size_t count, std::vector<uint32_t>& out,
                      std::string& error) {
  auto fail = [&](std::string why) {
    error = "obs_point_id_packed: " + std::move(why);
    return false;
  };
  if (size < kHeaderBytes)
    return fail(std::to_string(size) + " bytes, shorter than the " + std::to_string(kHeaderBytes) + "-byte header");
  // The reader never throws here: the header's length was checked above.
  ByteReader header(data, size);
  const uint8_t coding = header.get<uint8_t>("coding");
  if (coding != kPointIdCoding)
    return fail("coding " + std::to_string(coding) + ", expected " + std::to_string(kPointIdCoding));
  IdClass classes[2];
  for (int c = 0; c < 2; ++c) {
    classes[c].base = header.get<uint32_t>("base");
    classes[c].bits = header.get<uint8_t>("bits");
    if (classes[c].bits > 31)
      return fail("class " + std::to_string(c) + " offsets in " + std::to_string(classes[c].bits) + " bits, at most 31");
  }
  // Each id takes at least its class bit: a count the bytes cannot hold is refused before allocating.
  if (count > 8 * (size - kHeaderBytes))
    return fail(std::to_string(count) + " ids do not fit in " + std::to_string(size) + " bytes");
  out.assign(count, 0);
  BitReader bits(data + kHeaderBytes, size - kHeaderBytes);
  for (size_t i = 0; i < count; ++i) {
    uint32_t is_high = 0, offset = 0;
    if (!bits.get(1, is_high) || !bits.get(classes[is_high].bits, offset))
      return fail("truncated at id " + std::to_string(i) + " of " + std::to_string(count));
    const uint64_t id = uint64_t{classes[is_high].base} + offset;
    if (is_high ? (id < kHighPointIds || id > UINT32_MAX) : id >= kHighPointIds)
      return fail("id " + std::to_string(id) + " at " + std::to_string(i) + " is outside its class (" +
                  (is_high ? "from 2^31" : "below 2^31") + ")");
    out[i] = static_cast<uint32_t>(id);
  }
  if (!bits.only_zero_padding_left())
    return fail("bytes or set bits after the last id (" + std::to_string(size) + " bytes)");
  return true;
}

}  // namespace edge_slam
