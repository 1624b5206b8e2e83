#include "edge_slam/module/last_frame_depth_points.h"

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "edge_slam/data/map_point.h"

namespace edge_slam {

bool is_depth_point(const MapPoint& mp) { return mp.id() == kDepthPointId; }

int add_depth_points(Frame& last, float close_depth, int min_points) {
  const FrameFeatures& f = last.feat();
  std::vector<std::pair<float, size_t>> by_depth;
  by_depth.reserve(last.size());
  for (size_t i = 0; i < last.size(); ++i)
    if (f.has_depth(i)) by_depth.emplace_back(f.depth[i], i);
  std::sort(by_depth.begin(), by_depth.end());
  if (last.outliers.size() != last.size()) last.outliers.assign(last.size(), false);
  if (last.map_points.size() != last.size()) last.map_points.assign(last.size(), nullptr);
  int points = 0, made = 0;
  for (const auto& [z, i] : by_depth) {
    if (z > close_depth && points >= min_points) break;
    ++points;
    auto& mp = last.map_points[i];
    // A map point, even one the last pose optimisation called an outlier, keeps its keypoint.
    if (mp && !mp->is_bad() && mp->num_observations() > 0) continue;
    mp = std::make_shared<MapPoint>(kDepthPointId, last.unproject_world(i), kNoId);
    mp->set_descriptor(f.descriptor(i));
    last.outliers[i] = false;
    ++made;
  }
  return made;
}

int count_depth_points(const Frame& frame) {
  int n = 0;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    const auto& mp = frame.map_points[i];
    n += mp && is_depth_point(*mp) && !(i < frame.outliers.size() && frame.outliers[i]) ? 1 : 0;
  }
  return n;
}

int drop_depth_points(Frame& frame) {
  int dropped = 0;
  for (size_t i = 0; i < frame.map_points.size(); ++i) {
    auto& mp = frame.map_points[i];
    if (!mp || !is_depth_point(*mp)) continue;
    mp = nullptr;
    if (i < frame.outliers.size()) {
      dropped += frame.outliers[i] ? 0 : 1;
      frame.outliers[i] = false;
    }
  }
  return dropped;
}

}  // namespace edge_slam
