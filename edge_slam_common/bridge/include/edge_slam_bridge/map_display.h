// rviz displays of a map, drawn the same way for the mobile's Local-Map and the edge's
// Global-Map: map points as a PointCloud2 (x, y, z float32), KeyFrames as markers.
#pragma once
#include <edge_slam/data/keyframe.h>
#include <edge_slam/data/map.h>
#include <edge_slam/data/map_point.h>
#include <ros/publisher.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <visualization_msgs/MarkerArray.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace edge_slam {

inline sensor_msgs::PointCloud2 to_point_cloud(const std::vector<std::shared_ptr<MapPoint>>& points,
                                               const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header.frame_id = frame_id;
  cloud.header.stamp = stamp;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(points.size());
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const auto& mp : points) {
    const Eigen::Vector3d p = mp->position();
    *x = static_cast<float>(p.x());
    *y = static_cast<float>(p.y());
    *z = static_cast<float>(p.z());
    ++x, ++y, ++z;
  }
  return cloud;
}

// KeyFrame centres as cubes and their spanning-tree links as lines, in one colour (r, g, b).
// Two markers in namespace `ns`; each call replaces the previous ones.
inline visualization_msgs::MarkerArray keyframe_markers(const std::vector<std::shared_ptr<KeyFrame>>& kfs,
                                                        const std::string& frame_id, const ros::Time& stamp,
                                                        const std::string& ns, float r, float g, float b) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker centres, tree;
  for (visualization_msgs::Marker* m : {&centres, &tree}) {
    m->header.frame_id = frame_id;
    m->header.stamp = stamp;
    m->ns = ns;
    m->action = visualization_msgs::Marker::ADD;
    m->pose.orientation.w = 1.0;
    m->color.r = r, m->color.g = g, m->color.b = b, m->color.a = 1.0f;
  }
  centres.id = 0;
  centres.type = visualization_msgs::Marker::CUBE_LIST;
  centres.scale.x = centres.scale.y = centres.scale.z = 0.04;
  tree.id = 1;
  tree.type = visualization_msgs::Marker::LINE_LIST;
  tree.scale.x = 0.008;
  std::unordered_map<uint32_t, Eigen::Vector3d> centre_of;
  for (const auto& kf : kfs) centre_of[kf->id()] = kf->T_wc().translation();
  auto point = [](const Eigen::Vector3d& c) {
    geometry_msgs::Point p;
    p.x = c.x(), p.y = c.y(), p.z = c.z();
    return p;
  };
  for (const auto& kf : kfs) {
    const Eigen::Vector3d& c = centre_of[kf->id()];
    centres.points.push_back(point(c));
    const auto parent = centre_of.find(kf->parent_id());
    if (parent == centre_of.end()) continue;
    tree.points.push_back(point(c));
    tree.points.push_back(point(parent->second));
  }
  out.markers.push_back(centres);
  if (tree.points.empty()) tree.action = visualization_msgs::Marker::DELETE;  // rviz rejects an empty LINE_LIST
  out.markers.push_back(tree);
  return out;
}

// Both displays of a map, each built only when someone is watching it (the Global-Map is large).
struct MapDisplay {
  ros::Publisher cloud, markers;
  std::string frame_id, ns;
  float r = 1, g = 1, b = 1;
  void publish(const Map& map, const ros::Time& stamp) const {
    if (cloud.getNumSubscribers() > 0) cloud.publish(to_point_cloud(map.map_points(), frame_id, stamp));
    if (markers.getNumSubscribers() > 0) markers.publish(keyframe_markers(map.keyframes(), frame_id, stamp, ns, r, g, b));
  }
};

}  // namespace edge_slam
