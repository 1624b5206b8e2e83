// The keypoint block of KeyFrame / Frame messages (io/keypoint_coding.h): lossless on any
// keypoints, compact on an extractor's (level by level, rows in order), and every malformed
// block refused with a message rather than read past its end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "edge_slam/io/keypoint_coding.h"

namespace edge_slam {
namespace {

// 1000 keypoints as the extractor emits them on a 640 x 480 image: 8 levels, each in row order.
std::vector<WireKeypoint> extractor_like(uint32_t seed) {
  std::mt19937 rng(seed);
  const int per_level[8] = {217, 181, 151, 126, 105, 87, 73, 60};
  std::vector<WireKeypoint> out;
  for (int level = 0; level < 8; ++level) {
    std::vector<WireKeypoint> kps(per_level[level]);
    for (WireKeypoint& kp : kps) {
      kp.x = static_cast<int16_t>(std::uniform_int_distribution<int>(-40, 5160)(rng));
      kp.y = static_cast<int16_t>(std::uniform_int_distribution<int>(-30, 3870)(rng));
      kp.octave = static_cast<uint8_t>(level);
      kp.angle = static_cast<uint8_t>(rng());
      kp.depth = rng() % 5 == 0 ? 0 : static_cast<uint16_t>(std::uniform_int_distribution<int>(2000, 20000)(rng));
    }
    std::sort(kps.begin(), kps.end(), [](const WireKeypoint& a, const WireKeypoint& b) { return a.y < b.y; });
    out.insert(out.end(), kps.begin(), kps.end());
  }
  return out;
}

std::vector<WireKeypoint> round_trip(const std::vector<WireKeypoint>& in) {
  const std::vector<uint8_t> block = encode_keypoints(in);
  std::vector<WireKeypoint> out;
  std::string error;
  EXPECT_TRUE(decode_keypoints(block.data(), block.size(), in.size(), out, error)) << error;
  EXPECT_LE(block.size(), max_keypoint_block_bytes(in.size()));
  return out;
}

TEST(KeypointCoding, GivesBackTheSameValuesAndCostsUnderSixBytesAKeypointInExtractorOrder) {
  const std::vector<WireKeypoint> in = extractor_like(1);
  const std::vector<uint8_t> block = encode_keypoints(in);
  EXPECT_EQ(round_trip(in), in);
  // The fixed-width fields were 8 bytes a keypoint (int16 x, y, uint8 octave, angle, uint16 depth).
  EXPECT_LT(block.size(), 6 * in.size()) << block.size() << " bytes";
}

TEST(KeypointCoding, AnyOrderAndTheWholeValueRangesComeBack) {
  std::mt19937 rng(7);
  std::vector<WireKeypoint> in(3000);
  for (WireKeypoint& kp : in) {
    kp.x = static_cast<int16_t>(rng());
    kp.y = static_cast<int16_t>(rng());
    kp.octave = static_cast<uint8_t>(rng() % (kMaxWireOctave + 1));
    kp.angle = static_cast<uint8_t>(rng());
    kp.depth = static_cast<uint16_t>(rng());
  }
  in[0].x = std::numeric_limits<int16_t>::min();
  in[1].x = std::numeric_limits<int16_t>::max();
  in[2].y = std::numeric_limits<int16_t>::min();
  in[3].y = std::numeric_limits<int16_t>::max();  // the largest y step there is
  in[4].depth = 65535;
  EXPECT_EQ(round_trip(in), in);
  EXPECT_EQ(round_trip({}), std::vector<WireKeypoint>{});
  EXPECT_EQ(round_trip({in[5]}), std::vector<WireKeypoint>{in[5]});
}

TEST(KeypointCoding, ARunLongerThanSixteenBitsIsSplit) {
  std::vector<WireKeypoint> in(70000);
  for (size_t i = 0; i < in.size(); ++i) in[i].y = static_cast<int16_t>(i % 3000);
  EXPECT_EQ(round_trip(in), in);
}

TEST(KeypointCoding, AnOctaveItCannotCodeIsAnError) {
  std::vector<WireKeypoint> in(2);
  in[1].octave = kMaxWireOctave + 1;
  EXPECT_THROW(encode_keypoints(in), std::invalid_argument);
}

std::string refusal(const std::vector<uint8_t>& block, size_t count) {
  std::vector<WireKeypoint> out;
  std::string error;
  EXPECT_FALSE(decode_keypoints(block.data(), block.size(), count, out, error));
  return error;
}

TEST(KeypointCoding, MalformedBlocksAreRefusedWithWhatWasExpected) {
  const std::vector<WireKeypoint> in = extractor_like(2);
  const std::vector<uint8_t> good = encode_keypoints(in);
  const size_t n = in.size();

  EXPECT_NE(refusal({}, n).find("header"), std::string::npos);
  EXPECT_NE(refusal({}, 0).find("header"), std::string::npos);
  { auto b = good; b[0] = 2; EXPECT_NE(refusal(b, n).find("coding 2"), std::string::npos); }
  { auto b = good; b[3] = 17; EXPECT_NE(refusal(b, n).find("at most 16"), std::string::npos); }
  { auto b = good; b[4] = 200; EXPECT_NE(refusal(b, n).find("at most 16"), std::string::npos); }
  EXPECT_NE(refusal(good, n - 1).find("descriptors 999 keypoints"), std::string::npos);
  EXPECT_NE(refusal(good, n + 1).find("descriptors 1001 keypoints"), std::string::npos);
  { auto b = good; b[7] = 32; EXPECT_NE(refusal(b, n).find("octave 32"), std::string::npos); }  // first run's octave
  { auto b = good; b[10] = 17; EXPECT_NE(refusal(b, n).find("Rice parameter 17"), std::string::npos); }
  { auto b = good; b[8] = 0; b[9] = 0; EXPECT_NE(refusal(b, n).find("empty"), std::string::npos); }
  { auto b = good; b[5] = 0xFF; b[6] = 0xFF; EXPECT_NE(refusal(b, n).find("runs for"), std::string::npos); }
  { auto b = good; b.resize(12); EXPECT_NE(refusal(b, n).find("run table"), std::string::npos); }
  { auto b = good; b.pop_back(); EXPECT_NE(refusal(b, n).find("truncated at keypoint"), std::string::npos); }
  { auto b = good; b.push_back(0); EXPECT_NE(refusal(b, n).find("after the last keypoint"), std::string::npos); }
}

// A block written bit by bit: header with one run (octave 0, `count`, Rice `k`), x_bits 0,
// depth_bits 0, x_min `x_min`, then `bits` (least significant first).
std::vector<uint8_t> handmade(int16_t x_min, uint8_t x_bits, uint16_t count, uint8_t k, const std::vector<int>& bits) {
  std::vector<uint8_t> b = {kKeypointCoding, static_cast<uint8_t>(x_min & 0xFF), static_cast<uint8_t>((x_min >> 8) & 0xFF),
                            x_bits, 0, 1, 0, 0, static_cast<uint8_t>(count & 0xFF), static_cast<uint8_t>(count >> 8), k};
  const size_t start = b.size();
  b.resize(start + (bits.size() + 7) / 8, 0);
  for (size_t i = 0; i < bits.size(); ++i)
    if (bits[i]) b[start + i / 8] |= static_cast<uint8_t>(1u << (i % 8));
  return b;
}
void append_value(std::vector<int>& bits, uint32_t value, int width) {
  for (int i = 0; i < width; ++i) bits.push_back((value >> i) & 1);
}

TEST(KeypointCoding, OutOfRangeCoordinatesAreRefused) {
  // Two steps of +32767 (zigzag 65534, Rice k = 16: a zero, 16 bits), angle 0 each: the second
  // keypoint's y would be 65534.
  std::vector<int> bits;
  for (int kp = 0; kp < 2; ++kp) {
    bits.push_back(0);
    append_value(bits, 65534, 16);
    append_value(bits, 0, 8);
  }
  EXPECT_NE(refusal(handmade(0, 0, 2, 16, bits), 2).find("y out of range at keypoint 1"), std::string::npos);
  bits.resize(25);  // the first keypoint alone is fine
  std::vector<WireKeypoint> out;
  std::string error;
  const auto one = handmade(0, 0, 1, 16, bits);
  ASSERT_TRUE(decode_keypoints(one.data(), one.size(), 1, out, error)) << error;
  EXPECT_EQ(out[0].y, 32767);
  auto padded = one;  // 25 bits: the last byte's 7 high bits are padding
  padded.back() |= 0x80;
  EXPECT_NE(refusal(padded, 1).find("after the last keypoint"), std::string::npos);

  // x_min 32767 with 1 bit of x, set: x = 32768.
  std::vector<int> xbits = {0};
  append_value(xbits, 0, 16);  // y step 0
  xbits.push_back(1);          // x - x_min = 1
  append_value(xbits, 0, 8);
  EXPECT_NE(refusal(handmade(32767, 1, 1, 16, xbits), 1).find("x out of range"), std::string::npos);
}

TEST(KeypointCoding, RandomBytesNeverReadPastTheBlock) {
  std::mt19937 rng(3);
  const std::vector<uint8_t> good = encode_keypoints(extractor_like(4));
  int accepted = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> b = good;
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int f = 0; f < flips; ++f) b[rng() % b.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    if (rng() % 4 == 0) b.resize(rng() % b.size());
    std::vector<WireKeypoint> out;
    std::string error;
    if (decode_keypoints(b.data(), b.size(), 1000, out, error)) {
      ++accepted;  // a flip in an angle or depth bit is a valid, different block
      EXPECT_EQ(out.size(), 1000u);
    } else {
      EXPECT_FALSE(error.empty());
    }
  }
  EXPECT_LT(accepted, 2000);
}

}  // namespace
}  // namespace edge_slam
