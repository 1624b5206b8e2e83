#include "edge_slam/io/map_records.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/record_checks.h"

namespace edge_slam {

CameraRecord to_camera_record(const PinholeCamera& c) {
  CameraRecord r;
  r.name = c.name;
  r.fx = c.fx;
  r.fy = c.fy;
  r.cx = c.cx;
  r.cy = c.cy;
  r.bf = c.bf;
  r.th_depth = static_cast<float>(c.th_depth);
  r.width = c.width;
  r.height = c.height;
  return r;
}

FeatureRecord to_feature_record(const FrameFeatures& f) {
  FeatureRecord r;
  r.keypoints = f.keys_un;
  r.depth = f.depth;
  r.descriptors = f.descriptors;  // shared, immutable: FrameFeatures never changes it
  return r;
}

KeyFrameRecord to_record(const KeyFrame& kf, const Map& map, const std::unordered_set<uint32_t>& created) {
  KeyFrameRecord r;
  r.id = kf.id();
  r.frame_id = static_cast<uint32_t>(kf.frame_id());
  r.stamp = kf.stamp();
  r.T_wc = kf.T_wc();
  r.camera = to_camera_record(kf.features().camera);
  r.features = to_feature_record(kf.features());
  const std::vector<uint32_t> ids = kf.map_point_ids();
  std::unordered_set<uint32_t> sent;  // receivers reject a point seen at two keypoints
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] == kNoId || !sent.insert(ids[i]).second) continue;
    const std::shared_ptr<MapPoint> mp = map.map_point(ids[i]);
    if (!mp || mp->is_bad()) continue;
    if (created.count(ids[i])) {
      r.new_points.push_back({ids[i], static_cast<uint32_t>(i), mp->position().cast<float>()});
    } else {
      r.observations.emplace_back(static_cast<uint32_t>(i), ids[i]);
    }
  }
  r.parent_id = kf.parent_id() == kf.id() ? kNoId : kf.parent_id();
  for (const auto& [id, weight] : kf.connection_weights())
    if (id != kf.id()) r.covisibility.emplace_back(id, static_cast<uint32_t>(std::max(weight, 0)));
  return r;
}

MapPointRecord to_record(const MapPoint& mp) {
  MapPointRecord r;
  r.id = mp.id();
  r.position = mp.position().cast<float>();
  r.descriptor = mp.descriptor();
  r.normal = mp.normal().cast<float>();
  r.min_distance = mp.min_distance();
  r.max_distance = mp.max_distance();
  r.ref_keyframe_id = mp.reference_kf_id();
  return r;
}

FrameRecord to_record(const Frame& frame, uint64_t seq) {
  FrameRecord r;
  r.seq = seq;
  r.id = static_cast<uint32_t>(frame.id);
  r.stamp = frame.stamp;
  r.camera = to_camera_record(frame.feat().camera);
  r.features = to_feature_record(frame.feat());
  return r;
}

std::string camera_mismatch(const CameraRecord& r, const PinholeCamera& c) {
  auto differs = [](double a, double b) { return !(std::abs(a - b) <= 1e-3 * std::max(1.0, std::abs(b))); };
  if (r.width != c.width || r.height != c.height)
    return "image size " + std::to_string(r.width) + "x" + std::to_string(r.height) + ", expected " +
           std::to_string(c.width) + "x" + std::to_string(c.height);
  if (differs(r.fx, c.fx) || differs(r.fy, c.fy) || differs(r.cx, c.cx) || differs(r.cy, c.cy))
    return "intrinsics (" + std::to_string(r.fx) + ", " + std::to_string(r.fy) + ", " + std::to_string(r.cx) +
           ", " + std::to_string(r.cy) + ") differ from the configured camera '" + c.name + "'";
  if (differs(r.bf, c.bf)) return "bf " + std::to_string(r.bf) + ", expected " + std::to_string(c.bf);
  return {};
}

std::shared_ptr<const FrameFeatures> features_from_record(const FeatureRecord& in, const CameraRecord& rc,
                                                          const PinholeCamera& camera,
                                                          std::shared_ptr<const ScalePyramid> pyramid) {
  const std::string mismatch = camera_mismatch(rc, camera);
  if (!mismatch.empty()) throw std::invalid_argument("camera mismatch: " + mismatch);
  if (std::string problem = feature_record_problem(in); !problem.empty())
    throw std::invalid_argument("feature record: " + problem);
  const size_t n = in.keypoints.size();
  for (const cv::KeyPoint& kp : in.keypoints)
    if (kp.octave < 0 || kp.octave >= pyramid->num_levels)
      throw std::invalid_argument("keypoint octave " + std::to_string(kp.octave) + " outside the " +
                                  std::to_string(pyramid->num_levels) + "-level pyramid");
  auto f = std::make_shared<FrameFeatures>();
  f->camera = camera;
  f->pyramid = std::move(pyramid);
  f->keys = in.keypoints;  // raw coordinates are not sent; the undistorted ones stand in
  f->keys_un = in.keypoints;
  f->depth = in.depth;
  f->right_x.assign(n, -1.f);
  for (size_t i = 0; i < n; ++i) {
    if (f->depth[i] > 0) f->right_x[i] = static_cast<float>(in.keypoints[i].pt.x - camera.bf / f->depth[i]);
    else f->depth[i] = -1.f;
  }
  f->descriptors = in.descriptors.clone();
  f->bounds = compute_image_bounds(camera);
  f->grid = FeatureGrid(f->keys_un, f->bounds);
  return f;
}

std::shared_ptr<KeyFrame> keyframe_from_record(const KeyFrameRecord& r, const PinholeCamera& camera,
                                               std::shared_ptr<const ScalePyramid> pyramid) {
  if (std::string problem = keyframe_record_problem(r); !problem.empty()) throw std::invalid_argument(problem);
  auto features = features_from_record(r.features, r.camera, camera, std::move(pyramid));
  auto kf = std::make_shared<KeyFrame>(r.id, r.frame_id, r.stamp, features, r.T_wc.inverse());
  for (const auto& [kp, point] : r.observations) kf->set_map_point_id(kp, point);
  for (const NewPointRecord& p : r.new_points) kf->set_map_point_id(p.kp_index, p.id);
  if (r.parent_id != kNoId) kf->set_parent(r.parent_id);
  return kf;
}

std::shared_ptr<MapPoint> map_point_from_record(const MapPointRecord& r) {
  if (std::string problem = map_point_record_problem(r); !problem.empty()) throw std::invalid_argument(problem);
  auto mp = std::make_shared<MapPoint>(r.id, r.position.cast<double>(), r.ref_keyframe_id);
  mp->set_descriptor(r.descriptor.data());
  // Records carry min_distance()/max_distance(), which include the 0.8 / 1.2 scale margins;
  // store the raw range so that the margins are not applied twice after every hop.
  mp->set_normal_and_distances(r.normal.cast<double>(), r.min_distance / 0.8f, r.max_distance / 1.2f);
  return mp;
}

std::shared_ptr<MapPoint> map_point_from_new_point(const NewPointRecord& r, const KeyFrame& kf) {
  if (r.id == kNoId || r.kp_index >= kf.features().size() || !r.position.allFinite())
    throw std::invalid_argument("new point " + std::to_string(r.id) + " is invalid for KeyFrame " +
                                std::to_string(kf.id()));
  auto mp = std::make_shared<MapPoint>(r.id, r.position.cast<double>(), kf.id());
  mp->set_descriptor(kf.features().descriptor(r.kp_index));
  return mp;
}

StagedUpdate stage_update(const MapUpdateRecord& update, const PinholeCamera& camera,
                          std::shared_ptr<const ScalePyramid> pyramid, const BowVocabulary* vocabulary) {
  if (std::string problem = map_update_record_problem(update); !problem.empty())
    throw std::invalid_argument("map update: " + problem);
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  kfs.reserve(update.keyframes.size());
  for (const KeyFrameRecord& r : update.keyframes) {
    kfs.push_back(keyframe_from_record(r, camera, pyramid));
    if (vocabulary) kfs.back()->compute_bow(*vocabulary);
  }
  std::vector<std::shared_ptr<MapPoint>> mps;
  mps.reserve(update.points.size());
  for (const MapPointRecord& r : update.points) mps.push_back(map_point_from_record(r));

  auto count_observations = [&kfs] {
    size_t n = 0;
    for (const auto& kf : kfs)
      for (uint32_t id : kf->map_point_ids()) n += id != kNoId;
    return n;
  };
  const size_t observations_before = count_observations();
  StagedUpdate staged;
  staged.map = std::make_unique<Map>();
  staged.map->rebuild(kfs, mps);
  staged.stats.keyframes = staged.map->num_keyframes();
  staged.stats.map_points = staged.map->num_map_points();
  staged.stats.dropped_observations = observations_before - count_observations();  // rebuild only removes
  return staged;
}

void install_update(Map& map, StagedUpdate& staged) {
  std::lock_guard<std::mutex> lock(map.update_mutex());
  map.adopt(*staged.map);
}

RebuildStats rebuild_from_update(Map& map, const MapUpdateRecord& update, const PinholeCamera& camera,
                                 std::shared_ptr<const ScalePyramid> pyramid, const BowVocabulary* vocabulary) {
  StagedUpdate staged = stage_update(update, camera, std::move(pyramid), vocabulary);
  install_update(map, staged);
  return staged.stats;
}

}  // namespace edge_slam
