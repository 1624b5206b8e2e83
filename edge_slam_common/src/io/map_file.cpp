#include "edge_slam/io/map_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "byte_codec.h"
#include "edge_slam/io/file_bytes.h"
#include "edge_slam/io/record_checks.h"

namespace edge_slam {
namespace {

constexpr char kMagic[8] = {'E', 'S', 'M', 'A', 'P', 'B', 'I', 'N'};
constexpr size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;
constexpr size_t kFeatureBytes = 5 * 4 + 4 + 4 + 32;  // x y size angle response, octave, depth, descriptor
constexpr size_t kPointBytes = 4 + 12 + 32 + 12 + 8 + 4;
constexpr size_t kMinKeyFrameBytes = 8 + 4 + 4 + 8 + 96 + 4 + 5 * 8 + 4 + 8 + 4 + 4 + 4 + 4 + 4 + 4;

void put_pose(ByteWriter& w, const Eigen::Isometry3d& T) {
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) w.put(T.matrix()(row, col));
}

Eigen::Isometry3d get_pose(ByteReader& in, const char* what) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 4; ++col) T.matrix()(row, col) = in.get<double>(what);
  return T;
}

void put_keyframe(ByteWriter& w, const KeyFrameRecord& r, const std::vector<uint32_t>& loops) {
  w.put(r.seq);
  w.put(r.id);
  w.put(r.frame_id);
  w.put(r.stamp);
  put_pose(w, r.T_wc);
  w.put_string(r.camera.name);
  for (double v : {r.camera.fx, r.camera.fy, r.camera.cx, r.camera.cy, r.camera.bf}) w.put(v);
  w.put(r.camera.th_depth);
  w.put(static_cast<int32_t>(r.camera.width));
  w.put(static_cast<int32_t>(r.camera.height));
  const FeatureRecord& f = r.features;
  w.put(static_cast<uint32_t>(f.size()));
  for (size_t i = 0; i < f.size(); ++i) {
    const cv::KeyPoint& kp = f.keypoints[i];
    for (float v : {kp.pt.x, kp.pt.y, kp.size, kp.angle, kp.response}) w.put(v);
    w.put(static_cast<int32_t>(kp.octave));
    w.put(f.depth[i]);
    w.put_bytes(f.descriptors.ptr<uint8_t>(static_cast<int>(i)), 32);
  }
  w.put(static_cast<uint32_t>(r.observations.size()));
  for (const auto& [kp, point] : r.observations) {
    w.put(kp);
    w.put(point);
  }
  w.put(static_cast<uint32_t>(r.new_points.size()));
  for (const NewPointRecord& p : r.new_points) {
    w.put(p.id);
    w.put(p.kp_index);
    for (int k = 0; k < 3; ++k) w.put(p.position[k]);
  }
  w.put(r.parent_id);
  w.put(static_cast<uint32_t>(r.covisibility.size()));
  for (const auto& [id, weight] : r.covisibility) {
    w.put(id);
    w.put(weight);
  }
  w.put(static_cast<uint32_t>(loops.size()));
  for (uint32_t id : loops) w.put(id);
}

KeyFrameRecord get_keyframe(ByteReader& in, std::vector<uint32_t>& loops) {
  KeyFrameRecord r;
  r.seq = in.get<uint64_t>("KeyFrame seq");
  r.id = in.get<uint32_t>("KeyFrame id");
  r.frame_id = in.get<uint32_t>("frame id");
  r.stamp = in.get<double>("stamp");
  r.T_wc = get_pose(in, "pose");
  r.camera.name = in.get_string(256, "camera name");
  r.camera.fx = in.get<double>("fx");
  r.camera.fy = in.get<double>("fy");
  r.camera.cx = in.get<double>("cx");
  r.camera.cy = in.get<double>("cy");
  r.camera.bf = in.get<double>("bf");
  r.camera.th_depth = in.get<float>("th_depth");
  r.camera.width = in.get<int32_t>("width");
  r.camera.height = in.get<int32_t>("height");
  const size_t n = in.count(kFeatureBytes, "keypoint");
  FeatureRecord& f = r.features;
  f.keypoints.resize(n);
  f.depth.resize(n);
  f.descriptors.create(static_cast<int>(n), 32, CV_8U);
  for (size_t i = 0; i < n; ++i) {
    cv::KeyPoint& kp = f.keypoints[i];
    kp.pt.x = in.get<float>("keypoint");
    kp.pt.y = in.get<float>("keypoint");
    kp.size = in.get<float>("keypoint");
    kp.angle = in.get<float>("keypoint");
    kp.response = in.get<float>("keypoint");
    kp.octave = in.get<int32_t>("octave");
    f.depth[i] = in.get<float>("depth");
    std::memcpy(f.descriptors.ptr<uint8_t>(static_cast<int>(i)), in.take(32, "descriptor"), 32);
  }
  r.observations.resize(in.count(8, "observation"));
  for (auto& [kp, point] : r.observations) {
    kp = in.get<uint32_t>("observation");
    point = in.get<uint32_t>("observation");
  }
  r.new_points.resize(in.count(20, "new point"));
  for (NewPointRecord& p : r.new_points) {
    p.id = in.get<uint32_t>("new point");
    p.kp_index = in.get<uint32_t>("new point");
    for (int k = 0; k < 3; ++k) p.position[k] = in.get<float>("new point");
  }
  r.parent_id = in.get<uint32_t>("parent id");
  r.covisibility.resize(in.count(8, "covisibility link"));
  for (auto& [id, weight] : r.covisibility) {
    id = in.get<uint32_t>("covisibility link");
    weight = in.get<uint32_t>("covisibility link");
  }
  loops.resize(in.count(4, "loop edge"));
  for (uint32_t& id : loops) id = in.get<uint32_t>("loop edge");
  return r;
}

void put_point(ByteWriter& w, const MapPointRecord& p) {
  w.put(p.id);
  for (int k = 0; k < 3; ++k) w.put(p.position[k]);
  w.put_bytes(p.descriptor.data(), 32);
  for (int k = 0; k < 3; ++k) w.put(p.normal[k]);
  w.put(p.min_distance);
  w.put(p.max_distance);
  w.put(p.ref_keyframe_id);
}

MapPointRecord get_point(ByteReader& in) {
  MapPointRecord p;
  p.id = in.get<uint32_t>("point id");
  for (int k = 0; k < 3; ++k) p.position[k] = in.get<float>("point position");
  std::memcpy(p.descriptor.data(), in.take(32, "point descriptor"), 32);
  for (int k = 0; k < 3; ++k) p.normal[k] = in.get<float>("point normal");
  p.min_distance = in.get<float>("point distance");
  p.max_distance = in.get<float>("point distance");
  p.ref_keyframe_id = in.get<uint32_t>("point reference");
  return p;
}

void put_ids(ByteWriter& w, const std::vector<uint32_t>& ids) {
  w.put(static_cast<uint32_t>(ids.size()));
  for (uint32_t id : ids) w.put(id);
}

void get_ids(ByteReader& in, std::vector<uint32_t>& ids) {
  ids.resize(in.count(4, "KeyFrame id list"));
  for (uint32_t& id : ids) id = in.get<uint32_t>("KeyFrame id list");
}

// Version 3's tail: the merge history.
void put_merges(ByteWriter& w, const MapSnapshot& s) {
  w.put(static_cast<uint32_t>(s.merges.size()));
  for (const MapMergeRecord& m : s.merges) {
    w.put(m.keyframe);
    w.put(m.loop_keyframe);
    w.put(m.group_from);
    w.put(m.group_into);
    w.put(m.matches);
    put_pose(w, m.T_into_from);
  }
}

void get_merges(ByteReader& in, MapSnapshot& s) {
  s.merges.resize(in.count(4 + 4 + 4 + 4 + 4 + 96, "merge"));
  for (MapMergeRecord& m : s.merges) {
    m.keyframe = in.get<uint32_t>("merge KeyFrame");
    m.loop_keyframe = in.get<uint32_t>("merge loop KeyFrame");
    m.group_from = in.get<int32_t>("merge group from");
    m.group_into = in.get<int32_t>("merge group into");
    m.matches = in.get<int32_t>("merge matches");
    m.T_into_from = get_pose(in, "merge pose");
  }
  // A merge joins two groups of the file (none of them exist with one robot).
  for (const MapMergeRecord& m : s.merges)
    for (int32_t g : {m.group_from, m.group_into})
      if (g < 0 || static_cast<size_t>(g) >= s.groups.size())
        throw std::runtime_error("a merge names group " + std::to_string(g) + " of " + std::to_string(s.groups.size()));
}

// Version 4's tail: the loop detector's history, each robot named as in the other sections.
void put_loop_detector(ByteWriter& w, const MapSnapshot& s) {
  w.put(static_cast<uint32_t>(s.loop_groups.size()));
  for (const LoopGroupRecord& g : s.loop_groups) {
    w.put(g.robot);
    w.put(g.consistency);
    put_ids(w, g.members);
  }
  w.put(static_cast<uint32_t>(s.loop_robots.size()));
  for (const LoopRobotRecord& r : s.loop_robots) {
    w.put(r.robot);
    for (const std::optional<uint32_t>& id : {r.newest_keyframe, r.last_loop_keyframe}) {
      w.put(static_cast<uint8_t>(id ? 1 : 0));
      w.put(id.value_or(0));
    }
  }
}

void get_loop_detector(ByteReader& in, MapSnapshot& s) {
  s.loop_groups.resize(in.count(4 + 4 + 4, "loop candidate group"));
  for (LoopGroupRecord& g : s.loop_groups) {
    g.robot = in.get<uint32_t>("loop group robot");
    g.consistency = in.get<int32_t>("loop group consistency");
    get_ids(in, g.members);
  }
  s.loop_robots.resize(in.count(4 + 2 * (1 + 4), "loop detector robot"));
  for (LoopRobotRecord& r : s.loop_robots) {
    r.robot = in.get<uint32_t>("loop detector robot");
    for (std::optional<uint32_t>* id : {&r.newest_keyframe, &r.last_loop_keyframe}) {
      const bool set = in.get<uint8_t>("loop detector KeyFrame flag") != 0;
      const uint32_t value = in.get<uint32_t>("loop detector KeyFrame");
      if (set) *id = value;
    }
  }
  // Each names a robot of the file (one robot: robot 0), and a count is never negative.
  const size_t robots = std::max<size_t>(1, s.robots.size());
  const auto check_robot = [&](const char* who, uint32_t robot) {
    if (robot >= robots)
      throw std::runtime_error(std::string(who) + " names robot " + std::to_string(robot) + " of " +
                               std::to_string(robots));
  };
  for (const LoopGroupRecord& g : s.loop_groups) {
    check_robot("a loop candidate group", g.robot);
    if (g.consistency < 0)
      throw std::runtime_error("a loop candidate group has consistency " + std::to_string(g.consistency));
  }
  for (const LoopRobotRecord& r : s.loop_robots) check_robot("the loop detector", r.robot);
}

// Version 2's tail: the several-robot sections (counts 0 with one robot).
void put_robot_sections(ByteWriter& w, const MapSnapshot& s) {
  w.put(static_cast<uint32_t>(s.robots.size()));
  for (const RobotMapSection& r : s.robots) {
    w.put(r.last_keyframe_seq);
    put_ids(w, r.received_keyframe_ids);
    put_ids(w, r.inserted_keyframe_ids);
  }
  w.put(static_cast<uint32_t>(s.epochs.size()));
  for (const MapEpochRecord& e : s.epochs) {
    w.put(e.robot);
    w.put(e.first_id);
    w.put(e.group);
    put_pose(w, e.T_group_epoch);
  }
  w.put(static_cast<uint32_t>(s.groups.size()));
  for (const MapGroupRecord& g : s.groups) {
    w.put(static_cast<uint8_t>(g.T_world_group ? 1 : 0));
    put_pose(w, g.T_world_group.value_or(Eigen::Isometry3d::Identity()));
    w.put(static_cast<uint8_t>(g.merged_away ? 1 : 0));
  }
}

void get_robot_sections(ByteReader& in, MapSnapshot& s) {
  s.robots.resize(in.count(8 + 4 + 4, "robot section"));
  for (RobotMapSection& r : s.robots) {
    r.last_keyframe_seq = in.get<uint64_t>("robot KeyFrame seq");
    get_ids(in, r.received_keyframe_ids);
    get_ids(in, r.inserted_keyframe_ids);
  }
  s.epochs.resize(in.count(4 + 4 + 4 + 96, "robot map"));
  for (MapEpochRecord& e : s.epochs) {
    e.robot = in.get<uint32_t>("robot map robot");
    e.first_id = in.get<uint32_t>("robot map first id");
    e.group = in.get<int32_t>("robot map group");
    e.T_group_epoch = get_pose(in, "robot map pose");
  }
  s.groups.resize(in.count(1 + 96 + 1, "map group"));
  for (MapGroupRecord& g : s.groups) {
    const bool placed = in.get<uint8_t>("map group placed") != 0;
    const Eigen::Isometry3d T = get_pose(in, "map group pose");
    if (placed) g.T_world_group = T;
    g.merged_away = in.get<uint8_t>("map group merged") != 0;
  }
  // Every map names a robot of the file and a group of it: nothing to resolve later.
  for (const MapEpochRecord& e : s.epochs) {
    if (e.robot >= s.robots.size())
      throw std::runtime_error("a robot map names robot " + std::to_string(e.robot) + " of " +
                               std::to_string(s.robots.size()));
    if (e.group < 0 || static_cast<size_t>(e.group) >= s.groups.size())
      throw std::runtime_error("a robot map names group " + std::to_string(e.group) + " of " +
                               std::to_string(s.groups.size()));
  }
}

[[noreturn]] void fail(const std::string& origin, const std::string& what) {
  throw std::runtime_error("map file '" + origin + "': " + what);
}

}  // namespace

std::vector<uint8_t> encode_map_file(const MapSnapshot& s) {
  ByteWriter w;
  w.put_bytes(kMagic, sizeof(kMagic));
  w.put(kMapFileVersion);
  w.put(uint32_t{0});
  w.put(uint64_t{0});  // payload size and checksum, filled in below
  w.put(uint64_t{0});
  w.put(s.next_keyframe_id);
  w.put(s.next_map_point_id);
  w.put(s.last_keyframe_seq);
  w.put(static_cast<uint32_t>(s.content.keyframes.size()));
  static const std::vector<uint32_t> kNoLoops;
  for (const KeyFrameRecord& kf : s.content.keyframes) {
    const auto it = s.loop_edges.find(kf.id);
    put_keyframe(w, kf, it == s.loop_edges.end() ? kNoLoops : it->second);
  }
  w.put(static_cast<uint32_t>(s.content.points.size()));
  for (const MapPointRecord& p : s.content.points) put_point(w, p);
  for (const std::vector<uint32_t>* ids : {&s.received_keyframe_ids, &s.inserted_keyframe_ids, &s.culled_keyframe_ids})
    put_ids(w, *ids);
  put_robot_sections(w, s);
  put_merges(w, s);
  put_loop_detector(w, s);
  std::vector<uint8_t>& bytes = w.bytes();
  const uint64_t payload = bytes.size() - kHeaderBytes;
  const uint64_t checksum = fnv1a64(bytes.data() + kHeaderBytes, payload);
  std::memcpy(bytes.data() + 16, &payload, 8);
  std::memcpy(bytes.data() + 24, &checksum, 8);
  return std::move(bytes);
}

MapSnapshot decode_map_file(const uint8_t* data, size_t size, const std::string& origin) {
  if (size < kHeaderBytes) fail(origin, "truncated: " + std::to_string(size) + " bytes, shorter than the header");
  if (std::memcmp(data, kMagic, sizeof(kMagic)) != 0) fail(origin, "not an edge_slam map file (bad magic)");
  ByteReader header(data + 8, kHeaderBytes - 8);
  const uint32_t version = header.get<uint32_t>("version");
  if (version < 1 || version > kMapFileVersion)
    fail(origin, "unsupported map file version " + std::to_string(version) + " (expected 1 to " +
                     std::to_string(kMapFileVersion) + ")");
  header.get<uint32_t>("reserved");
  const uint64_t payload = header.get<uint64_t>("payload size");
  const uint64_t checksum = header.get<uint64_t>("checksum");
  if (payload != size - kHeaderBytes)
    fail(origin, (payload > size - kHeaderBytes ? "truncated: " : "trailing data: ") + std::to_string(size) +
                     " bytes, the header promises " + std::to_string(kHeaderBytes + payload));
  if (fnv1a64(data + kHeaderBytes, payload) != checksum) fail(origin, "checksum mismatch (the file is corrupt)");

  MapSnapshot s;
  try {
    ByteReader in(data + kHeaderBytes, payload);
    s.next_keyframe_id = in.get<uint32_t>("next KeyFrame id");
    s.next_map_point_id = in.get<uint32_t>("next map point id");
    s.last_keyframe_seq = in.get<uint64_t>("last KeyFrame seq");
    s.content.keyframes.resize(in.count(kMinKeyFrameBytes, "KeyFrame"));
    for (KeyFrameRecord& kf : s.content.keyframes) {
      std::vector<uint32_t> loops;
      kf = get_keyframe(in, loops);
      if (!loops.empty()) s.loop_edges[kf.id] = std::move(loops);
    }
    s.content.points.resize(in.count(kPointBytes, "map point"));
    for (MapPointRecord& p : s.content.points) p = get_point(in);
    for (std::vector<uint32_t>* ids : {&s.received_keyframe_ids, &s.inserted_keyframe_ids, &s.culled_keyframe_ids})
      get_ids(in, *ids);
    if (version >= 2) get_robot_sections(in, s);
    if (version >= 3) get_merges(in, s);
    if (version >= 4) get_loop_detector(in, s);
    if (in.remaining() != 0) throw std::runtime_error(std::to_string(in.remaining()) + " unread payload bytes");
  } catch (const std::runtime_error& e) {
    fail(origin, e.what());
  }
  if (std::string problem = map_update_record_problem(s.content); !problem.empty()) fail(origin, problem);
  return s;
}

void write_map_file(const MapSnapshot& s, const std::string& path) {
  const std::vector<uint8_t> bytes = encode_map_file(s);
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail(path, std::string("cannot create ") + tmp + ": " + std::strerror(errno));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      std::remove(tmp.c_str());
      fail(path, "write error: " + why);
    }
    done += static_cast<size_t>(n);
  }
  // Data on disk before the rename makes it visible: a crash leaves the old or the new file.
  const bool synced = ::fsync(fd) == 0;
  const bool closed = ::close(fd) == 0;
  if (!synced || !closed || std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    fail(path, "cannot complete the write: " + why);
  }
}

MapSnapshot read_map_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path, "map");
  return decode_map_file(bytes.data(), bytes.size(), path);
}

}  // namespace edge_slam
