// Map points as a PointCloud2 (x, y, z float32) for rviz: the mobile's Local-Map and the
// edge's Global-Map are drawn the same way.
#pragma once
#include <edge_slam/data/map_point.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <memory>
#include <string>
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

}  // namespace edge_slam
