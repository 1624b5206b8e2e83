#include "edge_slam/io/keypoint_coding.h"

#include "bit_stream.h"
#include "byte_codec.h"

#include <algorithm>
#include <stdexcept>

namespace edge_slam {
namespace {

constexpr size_t kHeaderBytes = 1 + 2 + 1 + 1 + 2;
constexpr size_t kRunBytes = 1 + 2 + 1;
constexpr uint32_t kMaxRice = 16;
constexpr uint32_t kEscapedBits = 17;  // a zigzagged difference of two int16 values

uint32_t zigzag(int32_t d) { return d >= 0 ? static_cast<uint32_t>(d) << 1 : (static_cast<uint32_t>(-d) << 1) - 1; }
int32_t unzigzag(uint32_t v) { return (v & 1u) ? -static_cast<int32_t>((v + 1) >> 1) : static_cast<int32_t>(v >> 1); }

uint32_t rice_bits(uint32_t v, uint32_t k) {
  const uint32_t q = v >> k;
  return q < kRiceEscape ? q + 1 + k : kRiceEscape + kEscapedBits;
}

struct Run {
  uint8_t octave;
  size_t begin, end;
  uint32_t k;
};

}  // namespace

std::vector<uint8_t> encode_keypoints(const std::vector<WireKeypoint>& keypoints) {
  const size_t n = keypoints.size();
  int16_t x_min = 0;
  int32_t x_max = 0;
  uint16_t depth_max = 0;
  for (size_t i = 0; i < n; ++i) {
    const WireKeypoint& kp = keypoints[i];
    if (kp.octave > kMaxWireOctave)
      throw std::invalid_argument("encode_keypoints: octave " + std::to_string(kp.octave) + " above " +
                                  std::to_string(kMaxWireOctave));
    x_min = i == 0 ? kp.x : std::min(x_min, kp.x);
    x_max = i == 0 ? kp.x : std::max<int32_t>(x_max, kp.x);
    depth_max = std::max(depth_max, kp.depth);
  }
  const uint32_t x_bits = n == 0 ? 0 : bits_for(static_cast<uint32_t>(x_max - x_min));
  const uint32_t depth_bits = bits_for(depth_max);

  // Runs of one octave (a count fits 16 bits), each with the Rice parameter that codes its y
  // differences in the fewest bits.
  std::vector<uint32_t> v(n);
  int32_t previous_y = 0;
  for (size_t i = 0; i < n; ++i) {
    v[i] = zigzag(int32_t{keypoints[i].y} - previous_y);
    previous_y = keypoints[i].y;
  }
  std::vector<Run> runs;
  for (size_t i = 0; i < n;) {
    size_t j = i + 1;
    while (j < n && keypoints[j].octave == keypoints[i].octave && j - i < 0xFFFF) ++j;
    Run run{keypoints[i].octave, i, j, 0};
    uint64_t best = UINT64_MAX;
    for (uint32_t k = 0; k <= kMaxRice; ++k) {
      uint64_t bits = 0;
      for (size_t a = i; a < j; ++a) bits += rice_bits(v[a], k);
      if (bits < best) best = bits, run.k = k;
    }
    runs.push_back(run);
    i = j;
  }
  if (runs.size() > 0xFFFF) throw std::invalid_argument("encode_keypoints: more than 65535 octave runs");

  ByteWriter header;
  header.put(kKeypointCoding);
  header.put(x_min);
  header.put(static_cast<uint8_t>(x_bits));
  header.put(static_cast<uint8_t>(depth_bits));
  header.put(static_cast<uint16_t>(runs.size()));
  for (const Run& run : runs) {
    header.put(run.octave);
    header.put(static_cast<uint16_t>(run.end - run.begin));
    header.put(static_cast<uint8_t>(run.k));
  }
  std::vector<uint8_t> out = std::move(header.bytes());
  BitWriter bits(out);
  for (const Run& run : runs) {
    for (size_t i = run.begin; i < run.end; ++i) {
      const WireKeypoint& kp = keypoints[i];
      const uint32_t q = v[i] >> run.k;
      if (q < kRiceEscape) {
        bits.put_ones_then_zero(q);
        bits.put(v[i], run.k);
      } else {
        for (uint32_t o = 0; o < kRiceEscape; ++o) bits.put_bit(1);
        bits.put(v[i], kEscapedBits);
      }
      bits.put(static_cast<uint32_t>(int32_t{kp.x} - x_min), x_bits);
      bits.put(kp.angle, 8);
      bits.put(kp.depth, depth_bits);
    }
  }
  return out;
}

bool decode_keypoints(const uint8_t* data, size_t size, size_t count, std::vector<WireKeypoint>& out,
                      std::string& error) {
  auto fail = [&](std::string why) {
    error = "keypoints: " + std::move(why);
    return false;
  };
  if (size < kHeaderBytes)
    return fail(std::to_string(size) + " bytes, shorter than the " + std::to_string(kHeaderBytes) + "-byte header");
  // The reader never throws here: every read is within a length checked before it.
  ByteReader header(data, size);
  const uint8_t coding = header.get<uint8_t>("coding");
  if (coding != kKeypointCoding)
    return fail("coding " + std::to_string(coding) + ", expected " + std::to_string(kKeypointCoding));
  const int16_t x_min = header.get<int16_t>("x_min");
  const uint32_t x_bits = header.get<uint8_t>("x_bits");
  const uint32_t depth_bits = header.get<uint8_t>("depth_bits");
  const size_t run_count = header.get<uint16_t>("runs");
  if (x_bits > 16 || depth_bits > 16)
    return fail("x_bits " + std::to_string(x_bits) + " / depth_bits " + std::to_string(depth_bits) + ", at most 16");
  if (run_count > count) return fail(std::to_string(run_count) + " runs for " + std::to_string(count) + " keypoints");
  const size_t runs_end = kHeaderBytes + kRunBytes * run_count;
  if (size < runs_end) return fail("truncated in the run table");
  std::vector<Run> runs(run_count);
  size_t total = 0;
  for (size_t r = 0; r < run_count; ++r) {
    const uint8_t octave = header.get<uint8_t>("octave");
    const size_t length = header.get<uint16_t>("count");
    runs[r] = {octave, total, total + length, header.get<uint8_t>("k")};
    if (runs[r].octave > kMaxWireOctave)
      return fail("run " + std::to_string(r) + " has octave " + std::to_string(runs[r].octave) + ", at most " +
                  std::to_string(kMaxWireOctave));
    if (length == 0) return fail("run " + std::to_string(r) + " is empty");
    if (runs[r].k > kMaxRice)
      return fail("run " + std::to_string(r) + " has Rice parameter " + std::to_string(runs[r].k) + ", at most 16");
    total += length;
  }
  if (total != count)
    return fail("the runs hold " + std::to_string(total) + " keypoints, the descriptors " + std::to_string(count) +
                " keypoints (32 bytes each)");

  out.assign(count, WireKeypoint{});
  BitReader bits(data + runs_end, size - runs_end);
  int32_t previous_y = 0;
  for (const Run& run : runs) {
    for (size_t i = run.begin; i < run.end; ++i) {
      WireKeypoint& kp = out[i];
      uint32_t q = 0, v = 0, x = 0, angle = 0, depth = 0;
      if (!bits.count_ones(kRiceEscape, q)) return fail("truncated at keypoint " + std::to_string(i));
      const bool ok = q < kRiceEscape ? bits.get(run.k, v) : bits.get(kEscapedBits, v);
      if (!ok) return fail("truncated at keypoint " + std::to_string(i));
      if (q < kRiceEscape) v |= q << run.k;
      const int32_t y = previous_y + unzigzag(v);
      if (y < INT16_MIN || y > INT16_MAX) return fail("y out of range at keypoint " + std::to_string(i));
      if (!bits.get(x_bits, x) || !bits.get(8, angle) || !bits.get(depth_bits, depth))
        return fail("truncated at keypoint " + std::to_string(i));
      if (int32_t{x_min} + static_cast<int32_t>(x) > INT16_MAX)
        return fail("x out of range at keypoint " + std::to_string(i));
      kp.x = static_cast<int16_t>(x_min + static_cast<int32_t>(x));
      kp.y = static_cast<int16_t>(y);
      kp.octave = run.octave;
      kp.angle = static_cast<uint8_t>(angle);
      kp.depth = static_cast<uint16_t>(depth);
      previous_y = y;
    }
  }
  if (!bits.only_zero_padding_left())
    return fail("bytes or set bits after the last keypoint (" + std::to_string(size) + " bytes)");
  return true;
}

size_t max_keypoint_block_bytes(size_t count) {
  const size_t max_bits = kRiceEscape + kEscapedBits + 16 + 8 + 16;
  return kHeaderBytes + kRunBytes * count + (count * max_bits + 7) / 8;
}

}  // namespace edge_slam
