// Mobile and edge allocate map point ids from disjoint halves, even across rebuilds that
// bring in the other side's points.
#include <gtest/gtest.h>

#include "edge_slam/data/map.h"

namespace edge_slam {
namespace {

std::shared_ptr<MapPoint> point(uint32_t id) {
  return std::make_shared<MapPoint>(id, Eigen::Vector3d(0, 0, 1), 0);
}

TEST(MapIdSpace, ForeignIdsDoNotMoveTheAllocator) {
  Map mobile;
  mobile.set_map_point_id_space(kMobilePointIdFirst, kEdgePointIdFirst);
  mobile.add_map_point(point(mobile.new_map_point_id()));
  mobile.add_map_point(point(mobile.new_map_point_id()));
  // A Local-Map update carries mobile points and points the edge triangulated.
  mobile.rebuild({}, {point(1), point(7), point(kEdgePointIdFirst + 40)});
  EXPECT_EQ(mobile.new_map_point_id(), 8u);

  Map edge;
  edge.set_map_point_id_space(kEdgePointIdFirst, kNoId);
  edge.add_map_point(point(5000));  // received from the mobile
  EXPECT_EQ(edge.new_map_point_id(), kEdgePointIdFirst);
  edge.add_map_point(point(kEdgePointIdFirst + 9));
  EXPECT_EQ(edge.new_map_point_id(), kEdgePointIdFirst + 10);
}

TEST(MapIdSpace, SettingTheSpaceStartsAboveExistingOwnIds) {
  Map m;
  m.add_map_point(point(3));
  m.add_map_point(point(kEdgePointIdFirst + 2));
  m.set_map_point_id_space(kEdgePointIdFirst, kNoId);
  EXPECT_EQ(m.new_map_point_id(), kEdgePointIdFirst + 3);
}

}  // namespace
}  // namespace edge_slam
