// 10,000 randomly mutated serialized KeyFrame / Frame / MapUpdate messages go through the
// receivers' whole path (checked deserialization, decoding, map building) without a crash;
// a rejected MapUpdate leaves the Local-Map exactly as it was. The mix of outcomes is printed.
#include <edge_slam/data/map.h>
#include <edge_slam/io/map_records.h>
#include <edge_slam_bridge/checked_deserialization.h>
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include <cstring>
#include <random>

#include "support/wire_fixtures.h"

namespace edge_slam {
namespace {

// One to four edits: flipped bits, overwritten 32-bit words (lengths, ids, counts), cuts.
std::vector<uint8_t> mutate(std::vector<uint8_t> b, std::mt19937& rng) {
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !b.empty(); ++e) {
    const size_t at = rng() % b.size();
    switch (rng() % 4) {
      case 0: b[at] ^= static_cast<uint8_t>(1u << (rng() % 8)); break;
      case 1: {
        const uint32_t words[] = {0u, 1u, 0xffffffffu, 0x7fffffffu, static_cast<uint32_t>(rng())};
        const uint32_t w = words[rng() % 5];
        std::memcpy(&b[at], &w, std::min<size_t>(4, b.size() - at));
        break;
      }
      case 2: b.resize(at); break;
      default: {  // a copy of the first bytes inserted (a shifted tail)
        const std::vector<uint8_t> head(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(std::min<size_t>(at, 16)));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), head.begin(), head.end());
        break;
      }
    }
  }
  return b;
}

struct Outcomes {
  int undecodable = 0, invalid = 0, refused_by_map = 0, accepted = 0;
};

TEST(BridgeMutations, TenThousandMutatedMessagesNeverCrashAndRejectedOnesChangeNothing) {
  const PinholeCamera camera = fixtures::pinhole_camera();
  const auto pyramid = std::make_shared<const ScalePyramid>(ScalePyramid::make(8, 1.2f));
  const MapUpdateRecord baseline = fixtures::map_update(3, 30, 20);
  const std::vector<uint8_t> update = fixtures::serialized(to_message(baseline));
  const std::vector<uint8_t> keyframe = fixtures::serialized(to_message(fixtures::keyframe(4, 40, 15, 10)));
  const std::vector<uint8_t> frame = fixtures::serialized(to_message(fixtures::frame(40)));
  Map local_map;
  rebuild_from_update(local_map, baseline, camera, pyramid, nullptr);
  const size_t keyframes = local_map.num_keyframes(), points = local_map.num_map_points();

  std::mt19937 rng(2024);
  Outcomes o;
  for (int i = 0; i < 10000; ++i) {
    const int kind = i % 3;
    const std::vector<uint8_t> b = mutate(kind == 0 ? update : kind == 1 ? keyframe : frame, rng);
    if (kind == 0) {
      edge_slam_msgs::MapUpdate msg;
      MapUpdateRecord r;
      if (!deserialize_checked(b.data(), b.size(), msg).ok) {
        ++o.undecodable;
      } else if (!from_message(msg, r).ok) {
        ++o.invalid;
      } else {
        try {
          rebuild_from_update(local_map, r, camera, pyramid, nullptr);
          ++o.accepted;
          rebuild_from_update(local_map, baseline, camera, pyramid, nullptr);  // next round starts equal
        } catch (const std::invalid_argument&) {
          ++o.refused_by_map;
        }
      }
      ASSERT_EQ(local_map.num_keyframes(), keyframes) << "mutation " << i;
      ASSERT_EQ(local_map.num_map_points(), points) << "mutation " << i;
    } else if (kind == 1) {
      edge_slam_msgs::KeyFrame msg;
      KeyFrameRecord r;
      if (!deserialize_checked(b.data(), b.size(), msg).ok) {
        ++o.undecodable;
      } else if (!from_message(msg, r).ok) {
        ++o.invalid;
      } else {
        try {
          const auto kf = keyframe_from_record(r, camera, pyramid);
          for (const NewPointRecord& p : r.new_points) map_point_from_new_point(p, *kf);
          ++o.accepted;
        } catch (const std::invalid_argument&) {
          ++o.refused_by_map;
        }
      }
    } else {
      edge_slam_msgs::Frame msg;
      FrameRecord r;
      if (!deserialize_checked(b.data(), b.size(), msg).ok) {
        ++o.undecodable;
      } else if (!from_message(msg, r).ok) {
        ++o.invalid;
      } else {
        try {
          features_from_record(r.features, r.camera, camera, pyramid);
          ++o.accepted;
        } catch (const std::invalid_argument&) {
          ++o.refused_by_map;
        }
      }
    }
  }
  std::cout << "10000 mutated messages: " << o.undecodable << " undecodable, " << o.invalid
            << " invalid fields, " << o.refused_by_map << " refused when building map objects (camera etc.), "
            << o.accepted << " still valid (e.g. a flipped descriptor bit)\n";
  EXPECT_EQ(o.undecodable + o.invalid + o.refused_by_map + o.accepted, 10000);
  EXPECT_GT(o.undecodable + o.invalid + o.refused_by_map, 5000) << "most mutations break a rule";
}

}  // namespace
}  // namespace edge_slam
