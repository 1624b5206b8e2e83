// InstanceCount counts the objects of one type alive: constructions of every kind add one,
// destructions take it back, assignments change nothing, and types count apart.
#include <gtest/gtest.h>

#include <memory>
#include <utility>
#include <vector>

#include "edge_slam/data/map_point.h"
#include "edge_slam/util/instance_count.h"

namespace edge_slam {
namespace {

struct Counted {
  int value = 0;
  InstanceCount<Counted> instance_count_;
};
struct OtherCounted {
  InstanceCount<OtherCounted> instance_count_;
};

TEST(InstanceCount, FollowsConstructionCopyMoveAndDestruction) {
  const int64_t before = InstanceCount<Counted>::alive();
  {
    Counted a;
    EXPECT_EQ(InstanceCount<Counted>::alive(), before + 1);
    Counted b = a;             // copy
    Counted c = std::move(a);  // move: the moved-from object is still alive
    EXPECT_EQ(InstanceCount<Counted>::alive(), before + 3);
    b = c;  // assignments make no object
    c = std::move(b);
    EXPECT_EQ(InstanceCount<Counted>::alive(), before + 3);
    std::vector<Counted> many(100);
    EXPECT_EQ(InstanceCount<Counted>::alive(), before + 103);
    EXPECT_EQ(InstanceCount<OtherCounted>::alive(), 0) << "each type has its own count";
  }
  EXPECT_EQ(InstanceCount<Counted>::alive(), before);
}

TEST(InstanceCount, CountsMapPointsHeldBySharedPointers) {
  const int64_t before = InstanceCount<MapPoint>::alive();
  auto p = std::make_shared<MapPoint>(7, Eigen::Vector3d(0, 0, 1), 0);
  std::shared_ptr<MapPoint> q = p;
  EXPECT_EQ(InstanceCount<MapPoint>::alive(), before + 1);
  p.reset();
  EXPECT_EQ(InstanceCount<MapPoint>::alive(), before + 1) << "still held";
  q.reset();
  EXPECT_EQ(InstanceCount<MapPoint>::alive(), before);
}

}  // namespace
}  // namespace edge_slam
