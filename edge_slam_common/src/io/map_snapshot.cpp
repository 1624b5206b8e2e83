#include "edge_slam/io/map_snapshot.h"

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/map_records.h"

namespace edge_slam {

MapSnapshot snapshot_map(const Map& map) {
  MapSnapshot s;
  for (const auto& kf : map.keyframes()) {
    if (kf->is_bad()) continue;
    s.content.keyframes.push_back(to_record(*kf, map));
    const std::set<uint32_t> loops = kf->loop_edges();
    if (!loops.empty()) s.loop_edges[kf->id()].assign(loops.begin(), loops.end());
  }
  for (const auto& mp : map.map_points())
    if (!mp->is_bad()) s.content.points.push_back(to_record(*mp));
  s.next_keyframe_id = map.next_keyframe_id();
  s.next_map_point_id = map.next_map_point_id();
  return s;
}

MapObjects map_objects_from_snapshot(const MapSnapshot& s, const PinholeCamera& camera,
                                     std::shared_ptr<const ScalePyramid> pyramid, const BowVocabulary* vocabulary) {
  MapObjects o;
  o.keyframes.reserve(s.content.keyframes.size());
  for (const KeyFrameRecord& r : s.content.keyframes) {
    o.keyframes.push_back(keyframe_from_record(r, camera, pyramid));
    if (vocabulary && !vocabulary->empty()) o.keyframes.back()->compute_bow(*vocabulary);
  }
  o.points.reserve(s.content.points.size());
  for (const MapPointRecord& r : s.content.points) o.points.push_back(map_point_from_record(r));
  return o;
}

void install_snapshot(const MapSnapshot& s, const MapObjects& o, Map& map, KeyFrameDatabase& database) {
  map.rebuild(o.keyframes, o.points);  // observations, children; covisibility recomputed ...
  for (size_t i = 0; i < o.keyframes.size(); ++i) {
    // ... and replaced by the saved weights, so the restored graph is exactly the saved one.
    const auto& kf = o.keyframes[i];
    kf->clear_connections();
    for (const auto& [id, weight] : s.content.keyframes[i].covisibility)
      if (map.keyframe(id)) kf->add_connection(id, static_cast<int>(weight));
    if (const auto it = s.loop_edges.find(kf->id()); it != s.loop_edges.end())
      for (uint32_t id : it->second)
        if (id != kf->id() && map.keyframe(id)) kf->add_loop_edge(id);
  }
  map.reserve_ids(s.next_keyframe_id, s.next_map_point_id);
  database.clear();
  for (const auto& kf : o.keyframes)
    if (kf->has_bow()) database.add(kf);
}

}  // namespace edge_slam
