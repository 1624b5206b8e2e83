// The observed point ids of a KeyFrame message as one bit-packed block (io/point_id_coding.h):
// lossless for any ids (both allocators' halves, the extremes), a few bytes for a KeyFrame's
// recent points, and every malformed block refused with what was expected.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "edge_slam/io/point_id_coding.h"

namespace edge_slam {
namespace {

std::vector<uint32_t> round_trip(const std::vector<uint32_t>& in) {
  const std::vector<uint8_t> block = encode_point_ids(in);
  std::vector<uint32_t> out;
  std::string error;
  EXPECT_TRUE(decode_point_ids(block.data(), block.size(), in.size(), out, error)) << error;
  return out;
}

TEST(PointIdCoding, RecentIdsOfBothAllocatorsCostAboutSeventeenBitsAndComeBack) {
  // 320 observations as on fr1: mobile-made points over a span of ~40k ids, edge-made over ~8k.
  std::mt19937 rng(5);
  std::vector<uint32_t> in;
  for (int i = 0; i < 320; ++i)
    in.push_back(rng() % 3 == 0 ? kHighPointIds + 1200 + rng() % 8000 : 50000 + rng() % 40000);
  const std::vector<uint8_t> block = encode_point_ids(in);
  EXPECT_EQ(round_trip(in), in);
  EXPECT_LT(block.size(), 320u * 18u / 8u + 11u) << block.size() << " bytes against " << 4 * in.size();
}

TEST(PointIdCoding, AnyIdsComeBack) {
  EXPECT_EQ(round_trip({}), std::vector<uint32_t>{});
  EXPECT_EQ(round_trip({0}), std::vector<uint32_t>{0});
  const std::vector<uint32_t> extremes = {0, kHighPointIds - 1, kHighPointIds, 0xFFFFFFFFu, 7, 0xFFFFFFFEu};
  EXPECT_EQ(round_trip(extremes), extremes);
  std::mt19937 rng(9);
  std::vector<uint32_t> any(5000);
  for (uint32_t& id : any) id = rng();
  EXPECT_EQ(round_trip(any), any);
  const std::vector<uint32_t> only_high = {kHighPointIds + 5, kHighPointIds + 9};
  EXPECT_EQ(round_trip(only_high), only_high);
}

std::string refusal(const std::vector<uint8_t>& block, size_t count) {
  std::vector<uint32_t> out;
  std::string error;
  EXPECT_FALSE(decode_point_ids(block.data(), block.size(), count, out, error));
  return error;
}

TEST(PointIdCoding, MalformedBlocksAreRefusedWithWhatWasExpected) {
  const std::vector<uint32_t> ids = {1000, 1003, kHighPointIds + 4, 1001, kHighPointIds + 60};
  const std::vector<uint8_t> good = encode_point_ids(ids);
  EXPECT_NE(refusal({}, 0).find("header"), std::string::npos);
  { auto b = good; b[0] = 3; EXPECT_NE(refusal(b, 5).find("coding 3"), std::string::npos); }
  { auto b = good; b[5] = 32; EXPECT_NE(refusal(b, 5).find("at most 31"), std::string::npos); }
  { auto b = good; b[10] = 40; EXPECT_NE(refusal(b, 5).find("at most 31"), std::string::npos); }
  { auto b = good; b.pop_back(); EXPECT_NE(refusal(b, 5).find("truncated at id"), std::string::npos); }
  { auto b = good; b.push_back(0); EXPECT_NE(refusal(b, 5).find("after the last id"), std::string::npos); }
  EXPECT_NE(refusal(good, 6).find("truncated at id 5"), std::string::npos);
  EXPECT_NE(refusal(good, 100000).find("do not fit"), std::string::npos);
  // A low base at 2^31: its ids leave their class. A high base below 2^31 likewise.
  { auto b = good; b[4] = 0x80; EXPECT_NE(refusal(b, 5).find("outside its class"), std::string::npos); }
  { auto b = good; b[9] = 0x00; EXPECT_NE(refusal(b, 5).find("outside its class"), std::string::npos); }
  // A high base near the top with offsets past 2^32.
  {
    auto b = good;
    b[6] = b[7] = b[8] = 0xFF;
    b[9] = 0xFF;
    EXPECT_NE(refusal(b, 5).find("outside its class"), std::string::npos);
  }
}

TEST(PointIdCoding, RandomFlipsNeverReadPastTheBlock) {
  std::mt19937 rng(11);
  std::vector<uint32_t> ids(300);
  for (uint32_t& id : ids) id = rng() % 2 ? 2000 + rng() % 30000 : kHighPointIds + rng() % 9000;
  const std::vector<uint8_t> good = encode_point_ids(ids);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> b = good;
    b[rng() % b.size()] ^= static_cast<uint8_t>(1u << (rng() % 8));
    if (rng() % 3 == 0) b.resize(rng() % b.size());
    std::vector<uint32_t> out;
    std::string error;
    if (decode_point_ids(b.data(), b.size(), ids.size(), out, error))
      EXPECT_EQ(out.size(), ids.size());
    else
      EXPECT_FALSE(error.empty());
  }
}

}  // namespace
}  // namespace edge_slam
