// The Global-Map file: a map saved and loaded into a fresh Map + KeyFrameDatabase is the same
// map (ids, poses, observations, covisibility, tree, loop edges, id counters); corrupt,
// truncated and wrong-version files are refused with a reason.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>

#include "edge_slam/io/map_file.h"
#include "edge_slam/io/map_snapshot.h"
#include "support/record_map.h"

namespace edge_slam {
namespace {

using test_support::SyntheticMap;

std::string temp_path(const char* name) {
  return "/tmp/edge_slam_test_" + std::to_string(::getpid()) + "_" + name;
}

// The fixture's map with extra structure a Local-Map update would not carry.
struct SavedMap : SyntheticMap {
  SavedMap() {
    map.keyframe(0)->add_loop_edge(5);
    map.keyframe(5)->add_loop_edge(0);
    map.keyframe(4)->add_connection(0, 7);  // below the threshold: must survive verbatim
    map.keyframe(0)->add_connection(4, 7);
    map.map_point(1005)->set_normal_and_distances(Eigen::Vector3d(0, 0, 1), 0.5f, 3.f);
    map.reserve_ids(40, 5000);
  }
};

void expect_same_map(const Map& a, const Map& b) {
  ASSERT_EQ(a.num_keyframes(), b.num_keyframes());
  ASSERT_EQ(a.num_map_points(), b.num_map_points());
  for (const auto& kf : a.keyframes()) {
    const auto other = b.keyframe(kf->id());
    ASSERT_TRUE(other) << "KeyFrame " << kf->id();
    EXPECT_EQ(other->frame_id(), kf->frame_id());
    EXPECT_DOUBLE_EQ(other->stamp(), kf->stamp());
    EXPECT_TRUE(other->T_cw().isApprox(kf->T_cw(), 1e-12));
    EXPECT_EQ(other->map_point_ids(), kf->map_point_ids());
    EXPECT_EQ(other->connection_weights(), kf->connection_weights()) << "KeyFrame " << kf->id();
    EXPECT_EQ(other->parent_id(), kf->parent_id());
    EXPECT_EQ(other->children(), kf->children());
    EXPECT_EQ(other->loop_edges(), kf->loop_edges());
    EXPECT_EQ(cv::norm(other->features().descriptors, kf->features().descriptors, cv::NORM_HAMMING), 0);
    EXPECT_EQ(other->features().depth, kf->features().depth);
  }
  for (const auto& mp : a.map_points()) {
    const auto other = b.map_point(mp->id());
    ASSERT_TRUE(other) << "point " << mp->id();
    EXPECT_TRUE(other->position().isApprox(mp->position(), 1e-6));
    EXPECT_EQ(other->descriptor(), mp->descriptor());
    EXPECT_EQ(other->observations(), mp->observations());
    EXPECT_NEAR(other->min_distance(), mp->min_distance(), 1e-5);
    EXPECT_NEAR(other->max_distance(), mp->max_distance(), 1e-5);
  }
  EXPECT_EQ(b.next_keyframe_id(), a.next_keyframe_id());
  EXPECT_EQ(b.next_map_point_id(), a.next_map_point_id());
}

TEST(MapFile, RoundTripThroughAFileGivesTheSameMap) {
  const SavedMap a;
  MapSnapshot saved = snapshot_map(a.map);
  saved.last_keyframe_seq = 77;
  saved.received_keyframe_ids = {0, 1, 2, 3, 4, 5, 9};
  saved.inserted_keyframe_ids = {0, 1, 2, 3, 4, 5};
  saved.culled_keyframe_ids = {7};
  const std::string path = temp_path("roundtrip.esmap");
  write_map_file(saved, path);
  std::ifstream tmp(path + ".tmp." + std::to_string(::getpid()));
  EXPECT_FALSE(tmp.good()) << "the temporary file is renamed away";

  const MapSnapshot loaded = read_map_file(path);
  std::remove(path.c_str());
  EXPECT_EQ(loaded.last_keyframe_seq, 77u);
  EXPECT_EQ(loaded.received_keyframe_ids, saved.received_keyframe_ids);
  EXPECT_EQ(loaded.inserted_keyframe_ids, saved.inserted_keyframe_ids);
  EXPECT_EQ(loaded.culled_keyframe_ids, saved.culled_keyframe_ids);
  const MapObjects objects = map_objects_from_snapshot(loaded, a.camera, a.pyramid, nullptr);
  Map b;
  KeyFrameDatabase database;
  install_snapshot(loaded, objects, b, database);
  expect_same_map(a.map, b);
  EXPECT_EQ(b.keyframe(4)->weight(0), 7);
}

TEST(MapFile, WritingReplacesAnExistingFile) {
  const SavedMap a;
  const std::string path = temp_path("replace.esmap");
  { std::ofstream(path) << "old content"; }
  write_map_file(snapshot_map(a.map), path);
  EXPECT_EQ(read_map_file(path).content.keyframes.size(), 6u);
  std::remove(path.c_str());
  EXPECT_THROW(write_map_file(snapshot_map(a.map), "/nonexistent_dir/x.esmap"), std::runtime_error);
}

void expect_refused(const std::vector<uint8_t>& bytes, const char* word) {
  try {
    decode_map_file(bytes.data(), bytes.size(), "test.esmap");
    ADD_FAILURE() << "accepted a file that should fail with '" << word << "'";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.esmap"), std::string::npos) << e.what();
  }
}

// Rewrites the checksum so a deliberately inconsistent payload reaches the record checks.
void reseal(std::vector<uint8_t>& bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (size_t i = 32; i < bytes.size(); ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
  std::memcpy(bytes.data() + 24, &h, 8);
}

// Two robots' sections: robot 1's map (KeyFrames from 16777216 on) merged into robot 0's.
void add_two_robots(MapSnapshot& s) {
  s.robots = {RobotMapSection{5, {1}, {1}}, RobotMapSection{9, {16777216}, {16777216}}};
  s.epochs = {MapEpochRecord{0, 0, 0, Eigen::Isometry3d::Identity()}, MapEpochRecord{1, 16777216, 0, Eigen::Isometry3d::Identity()}};
  s.groups = {MapGroupRecord{Eigen::Isometry3d::Identity(), false}, MapGroupRecord{std::nullopt, true}};
}

// The file an older version wrote: the current encoding without the tail bytes that version did
// not have, labelled with its version number (payload size and checksum made to match).
MapSnapshot decode_as_version(std::vector<uint8_t> bytes, uint32_t version, size_t tail_bytes) {
  bytes.resize(bytes.size() - tail_bytes);
  bytes[8] = static_cast<uint8_t>(version);
  const uint64_t payload = bytes.size() - 32;
  std::memcpy(bytes.data() + 16, &payload, 8);
  reseal(bytes);
  return decode_map_file(bytes.data(), bytes.size(), "v" + std::to_string(version) + ".esmap");
}

TEST(MapFile, CorruptTruncatedAndWrongVersionFilesAreRefused) {
  const SavedMap a;
  const std::vector<uint8_t> good = encode_map_file(snapshot_map(a.map));
  ASSERT_NO_THROW(decode_map_file(good.data(), good.size(), "test.esmap"));

  expect_refused({good.begin(), good.begin() + 20}, "truncated");
  expect_refused({good.begin(), good.end() - 1}, "truncated");
  auto bytes = good;
  bytes.push_back(0);
  expect_refused(bytes, "trailing");
  bytes = good;
  bytes[0] = 'X';
  expect_refused(bytes, "magic");
  bytes = good;
  bytes[8] = 5;
  expect_refused(bytes, "version 5");
  bytes = good;
  bytes[good.size() / 2] ^= 0x40;
  expect_refused(bytes, "checksum");

  // Consistent checksum, inconsistent content: the first KeyFrame's id becomes the reserved id.
  bytes = good;
  const size_t first_kf_id = 32 + 4 + 4 + 8 + 4 + 8;
  std::memset(bytes.data() + first_kf_id, 0xff, 4);
  reseal(bytes);
  expect_refused(bytes, "reserved");
  // A keypoint count far larger than the file: refused before allocating.
  bytes = good;
  const size_t first_count = first_kf_id + 4 + 4 + 8 + 96 + 4 + a.camera.name.size() + 40 + 4 + 8;
  const uint32_t huge = 0x7fffffff;
  std::memcpy(bytes.data() + first_count, &huge, 4);
  reseal(bytes);
  expect_refused(bytes, "does not fit");

  EXPECT_THROW(read_map_file("/nonexistent/map.esmap"), std::runtime_error);
}

TEST(MapFile, AVersionOneFileIsStillRead) {
  const SavedMap a;
  // Version 1 had no several-robot tail, merge history nor loop detector history (six zero
  // counts with one robot).
  const MapSnapshot loaded = decode_as_version(encode_map_file(snapshot_map(a.map)), 1, 6 * 4);
  EXPECT_EQ(loaded.content.keyframes.size(), 6u);
  EXPECT_TRUE(loaded.robots.empty());
}

TEST(MapFile, AVersionTwoFileIsReadWithoutAMergeHistory) {
  const SavedMap a;
  MapSnapshot saved = snapshot_map(a.map);
  add_two_robots(saved);
  // Version 2 ended with the groups: no merge nor loop detector counts.
  const MapSnapshot loaded = decode_as_version(encode_map_file(saved), 2, 3 * 4);
  EXPECT_EQ(loaded.robots.size(), 2u);
  EXPECT_EQ(loaded.groups.size(), 2u);
  EXPECT_TRUE(loaded.merges.empty());
}

TEST(MapFile, AVersionThreeFileIsReadWithoutALoopDetectorHistory) {
  const SavedMap a;
  MapSnapshot saved = snapshot_map(a.map);
  saved.loop_groups = {LoopGroupRecord{0, 2, {1, 2}}};
  // Version 3 ended with the merges: no loop detector history (the group count, the group with
  // its two members, the robot count).
  const MapSnapshot loaded = decode_as_version(encode_map_file(saved), 3, 4 + (4 + 4 + 4 + 2 * 4) + 4);
  EXPECT_EQ(loaded.content.keyframes.size(), 6u);
  EXPECT_TRUE(loaded.loop_groups.empty());
  EXPECT_TRUE(loaded.loop_robots.empty());
}

TEST(MapFile, TheLoopDetectorHistoryRoundTripsAndIsChecked) {
  const SavedMap a;
  MapSnapshot saved = snapshot_map(a.map);
  add_two_robots(saved);
  saved.loop_groups = {LoopGroupRecord{0, 2, {3, 4, 5}}, LoopGroupRecord{1, 0, {16777217}}};
  saved.loop_robots = {LoopRobotRecord{0, 40u, 31u}, LoopRobotRecord{1, 16777230u, std::nullopt}};
  const std::vector<uint8_t> good = encode_map_file(saved);
  const MapSnapshot loaded = decode_map_file(good.data(), good.size(), "test.esmap");
  ASSERT_EQ(loaded.loop_groups.size(), 2u);
  EXPECT_EQ(loaded.loop_groups[0].robot, 0u);
  EXPECT_EQ(loaded.loop_groups[0].consistency, 2);
  EXPECT_EQ(loaded.loop_groups[0].members, (std::vector<uint32_t>{3, 4, 5}));
  EXPECT_EQ(loaded.loop_groups[1].robot, 1u);
  EXPECT_EQ(loaded.loop_groups[1].members, (std::vector<uint32_t>{16777217}));
  ASSERT_EQ(loaded.loop_robots.size(), 2u);
  EXPECT_EQ(loaded.loop_robots[0].newest_keyframe, std::optional<uint32_t>(40));
  EXPECT_EQ(loaded.loop_robots[0].last_loop_keyframe, std::optional<uint32_t>(31));
  EXPECT_EQ(loaded.loop_robots[1].newest_keyframe, std::optional<uint32_t>(16777230));
  EXPECT_FALSE(loaded.loop_robots[1].last_loop_keyframe);

  MapSnapshot bad = saved;
  bad.loop_groups[1].robot = 2;  // the file has robots 0 and 1
  expect_refused(encode_map_file(bad), "loop candidate group names robot 2");
  bad = saved;
  bad.loop_groups[0].consistency = -1;
  expect_refused(encode_map_file(bad), "consistency -1");
  bad = saved;
  bad.loop_robots[1].robot = 7;
  expect_refused(encode_map_file(bad), "loop detector names robot 7");
  bad = snapshot_map(a.map);  // one robot: robot 0 only
  bad.loop_robots = {LoopRobotRecord{1, 3u, std::nullopt}};
  expect_refused(encode_map_file(bad), "loop detector names robot 1 of 1");
}

TEST(MapFile, SeveralRobotsSectionsRoundTripAndAreChecked) {
  const SavedMap a;
  MapSnapshot saved = snapshot_map(a.map);
  saved.robots = {RobotMapSection{5, {1, 2, 3}, {1, 3}}, RobotMapSection{9, {16777216}, {16777216}}};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1, 2, 3);
  saved.epochs = {MapEpochRecord{0, 0, 0, Eigen::Isometry3d::Identity()}, MapEpochRecord{1, 16777216, 0, T}};
  saved.groups = {MapGroupRecord{Eigen::Isometry3d::Identity(), false}, MapGroupRecord{std::nullopt, true}};
  saved.merges = {MapMergeRecord{16777220, 4, 1, 0, 87, T}};
  const std::vector<uint8_t> good = encode_map_file(saved);
  const MapSnapshot loaded = decode_map_file(good.data(), good.size(), "test.esmap");
  ASSERT_EQ(loaded.robots.size(), 2u);
  EXPECT_EQ(loaded.robots[1].last_keyframe_seq, 9u);
  EXPECT_EQ(loaded.robots[0].received_keyframe_ids, saved.robots[0].received_keyframe_ids);
  EXPECT_EQ(loaded.robots[0].inserted_keyframe_ids, saved.robots[0].inserted_keyframe_ids);
  ASSERT_EQ(loaded.epochs.size(), 2u);
  EXPECT_EQ(loaded.epochs[1].first_id, 16777216u);
  EXPECT_TRUE(loaded.epochs[1].T_group_epoch.isApprox(T));
  ASSERT_EQ(loaded.groups.size(), 2u);
  EXPECT_TRUE(loaded.groups[0].T_world_group);
  EXPECT_FALSE(loaded.groups[1].T_world_group);
  EXPECT_TRUE(loaded.groups[1].merged_away);
  ASSERT_EQ(loaded.merges.size(), 1u);
  EXPECT_EQ(loaded.merges[0].keyframe, 16777220u);
  EXPECT_EQ(loaded.merges[0].loop_keyframe, 4u);
  EXPECT_EQ(loaded.merges[0].group_from, 1);
  EXPECT_EQ(loaded.merges[0].group_into, 0);
  EXPECT_EQ(loaded.merges[0].matches, 87);
  EXPECT_TRUE(loaded.merges[0].T_into_from.isApprox(T));

  MapSnapshot bad = saved;
  bad.epochs[1].group = 2;  // no such group
  expect_refused(encode_map_file(bad), "names group 2");
  bad = saved;
  bad.merges[0].group_into = 5;
  expect_refused(encode_map_file(bad), "a merge names group 5");
}

TEST(MapFile, SnapshotForAnotherCameraIsRefusedOnRestore) {
  const SavedMap a;
  PinholeCamera other = a.camera;
  other.fx += 10;
  EXPECT_THROW(map_objects_from_snapshot(snapshot_map(a.map), other, a.pyramid, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace edge_slam
