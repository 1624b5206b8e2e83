#include "edge_slam/io/record_checks.h"

#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace edge_slam {
namespace {

bool bounded(double v) { return std::isfinite(v) && std::abs(v) <= kMaxRecordCoordinate; }
bool bounded(const Eigen::Vector3f& p) { return bounded(p.x()) && bounded(p.y()) && bounded(p.z()); }

std::string at(const char* what, size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

}  // namespace

std::string feature_record_problem(const FeatureRecord& f) {
  const size_t n = f.keypoints.size();
  if (f.depth.size() != n)
    return "depth holds " + std::to_string(f.depth.size()) + " values for " + std::to_string(n) + " keypoints";
  const bool empty_ok = n == 0 && f.descriptors.empty();
  if (!empty_ok && (f.descriptors.rows != static_cast<int>(n) || f.descriptors.cols != 32 ||
                    f.descriptors.type() != CV_8U || f.descriptors.dims != 2))
    return "descriptors must be " + std::to_string(n) + " x 32 bytes (CV_8U), got " +
           std::to_string(f.descriptors.rows) + " x " + std::to_string(f.descriptors.cols);
  for (size_t i = 0; i < n; ++i) {
    const cv::KeyPoint& kp = f.keypoints[i];
    if (!bounded(kp.pt.x) || !bounded(kp.pt.y)) return at("keypoint", i) + " position is not finite or out of range";
    if (!std::isfinite(kp.angle) || !std::isfinite(kp.size) || !std::isfinite(kp.response))
      return at("keypoint", i) + " angle/size/response is not finite";
    if (kp.octave < 0) return at("keypoint", i) + " has a negative octave";
    if (!std::isfinite(f.depth[i]) || f.depth[i] > kMaxRecordCoordinate)
      return at("depth", i) + " is not finite or out of range";
  }
  return {};
}

std::string pose_problem(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return "pose is not finite";
  if (!bounded(T.translation().x()) || !bounded(T.translation().y()) || !bounded(T.translation().z()))
    return "pose translation is out of range";
  const Eigen::Matrix3d R = T.linear();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-5 || R.determinant() < 0)
    return "pose rotation is not a rotation matrix";
  return {};
}

std::string keyframe_record_problem(const KeyFrameRecord& r) {
  const std::string who = "KeyFrame " + std::to_string(r.id) + ": ";
  if (r.id == kNoId) return "KeyFrame id is the reserved 'no id' value";
  if (!std::isfinite(r.stamp) || !std::isfinite(r.created_wall)) return who + "stamp or created_wall is not finite";
  if (std::string p = pose_problem(r.T_wc); !p.empty()) return who + p;
  if (std::string p = feature_record_problem(r.features); !p.empty()) return who + p;
  const size_t n = r.features.size();
  // One point per keypoint and one keypoint per point, as the map's observation tables assume.
  std::vector<uint8_t> keypoint_used(n, 0);
  std::unordered_set<uint32_t> points;
  auto claim = [&](uint32_t kp, uint32_t point, const std::string& where) -> std::string {
    if (kp >= n) return who + where + " keypoint index " + std::to_string(kp) + " >= " + std::to_string(n);
    if (point == kNoId) return who + where + " uses the reserved point id";
    if (keypoint_used[kp]++) return who + where + " reuses keypoint " + std::to_string(kp);
    if (!points.insert(point).second) return who + where + " repeats point " + std::to_string(point);
    return {};
  };
  for (size_t i = 0; i < r.observations.size(); ++i)
    if (std::string p = claim(r.observations[i].first, r.observations[i].second, at("observation", i)); !p.empty())
      return p;
  for (size_t i = 0; i < r.new_points.size(); ++i) {
    const NewPointRecord& np = r.new_points[i];
    if (std::string p = claim(np.kp_index, np.id, at("new point", i)); !p.empty()) return p;
    if (!bounded(np.position)) return who + at("new point", i) + " position is not finite or out of range";
  }
  if (r.parent_id == r.id) return who + "is its own spanning-tree parent";
  std::unordered_set<uint32_t> linked;
  for (const auto& [id, weight] : r.covisibility) {
    if (id == kNoId || id == r.id) return who + "covisibility link to the reserved id or to itself";
    if (!linked.insert(id).second) return who + "repeated covisibility link to " + std::to_string(id);
  }
  std::unordered_set<uint32_t> refuted;
  for (size_t i = 0; i < r.refuted_points.size(); ++i) {
    if (r.refuted_points[i] == kNoId) return who + at("refuted point", i) + " is the reserved point id";
    if (!refuted.insert(r.refuted_points[i]).second) return who + at("refuted point", i) + " is repeated";
  }
  return {};
}

std::string map_point_record_problem(const MapPointRecord& r) {
  const std::string who = "map point " + std::to_string(r.id) + ": ";
  if (r.id == kNoId) return "map point id is the reserved 'no id' value";
  if (!bounded(r.position)) return who + "position is not finite or out of range";
  if (!r.normal.allFinite() || r.normal.norm() > 1.01f) return who + "normal is not finite or longer than 1";
  if (!std::isfinite(r.min_distance) || !std::isfinite(r.max_distance) || r.min_distance < 0 ||
      r.max_distance < r.min_distance || r.max_distance > kMaxRecordCoordinate)
    return who + "distance range is not 0 <= min <= max <= " + std::to_string(kMaxRecordCoordinate);
  return {};
}

std::string map_update_record_problem(const MapUpdateRecord& u) {
  std::unordered_map<uint32_t, uint32_t> parent_of;  // within this update
  parent_of.reserve(u.keyframes.size());
  for (size_t i = 0; i < u.keyframes.size(); ++i) {
    const KeyFrameRecord& kf = u.keyframes[i];
    if (std::string p = keyframe_record_problem(kf); !p.empty()) return at("keyframes", i) + ": " + p;
    if (!parent_of.emplace(kf.id, kf.parent_id).second) return "KeyFrame id " + std::to_string(kf.id) + " repeats";
  }
  std::unordered_set<uint32_t> point_ids;
  point_ids.reserve(u.points.size());
  for (size_t i = 0; i < u.points.size(); ++i) {
    if (std::string p = map_point_record_problem(u.points[i]); !p.empty()) return at("points", i) + ": " + p;
    if (!point_ids.insert(u.points[i].id).second) return "map point id " + std::to_string(u.points[i].id) + " repeats";
  }
  // Spanning tree: walking up from any KeyFrame must leave the update without revisiting one.
  // Each KeyFrame is walked once overall (state 1 = on the current path, 2 = known to end).
  std::unordered_map<uint32_t, int> state;
  for (const auto& [start, unused] : parent_of) {
    std::vector<uint32_t> path;
    uint32_t id = start;
    while (true) {
      int& s = state[id];
      if (s == 2) break;
      if (s == 1) return "the spanning tree has a cycle through KeyFrame " + std::to_string(id);
      s = 1;
      path.push_back(id);
      const auto it = parent_of.find(id);
      if (it == parent_of.end()) break;
      const auto next = parent_of.find(it->second);
      if (next == parent_of.end()) break;
      id = next->first;
    }
    for (uint32_t p : path) state[p] = 2;
  }
  return {};
}

}  // namespace edge_slam
