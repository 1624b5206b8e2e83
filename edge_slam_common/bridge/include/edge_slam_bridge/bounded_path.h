// The trajectory as tracked shown in rviz (nav_msgs/Path): the newest `max_poses` poses only,
// published on every `every`-th pose (3 Hz at 15 fps is plenty for rviz).
//
// Why bounded, and why the bound is small: the path is published latched, so roscpp serialises
// the whole message on every publish whether anyone subscribes or not. With the former bound of
// 20,000 poses the mobile's path grew by ~100 bytes a frame for 22 minutes at 15 fps (the
// 0.15 MB/min of live heap the 20-minute long run showed beyond its Local-Map) and each publish
// serialised up to 1.8 MB, three times a second: a load that grows with the time the robot has
// been running. The poses' storage is reserved once, so it stays the same size all along, and
// the mobile nodelet only publishes while someone subscribes. Thread-safe: the image callback
// adds, a service clears.
#pragma once
#include <nav_msgs/Path.h>

#include <algorithm>
#include <cstddef>
#include <mutex>

namespace edge_slam {

class BoundedPath {
 public:
  static constexpr size_t kDefaultMaxPoses = 3000;  // 200 s at 15 fps

  explicit BoundedPath(size_t max_poses = kDefaultMaxPoses, unsigned every = 5) : every_(std::max(1u, every)) {
    set_max_poses(max_poses);
  }
  void set_max_poses(size_t max_poses) {
    std::lock_guard<std::mutex> lock(mutex_);
    max_poses_ = std::max<size_t>(1, max_poses);
    if (path_.poses.size() > max_poses_)
      path_.poses.erase(path_.poses.begin(), path_.poses.end() - static_cast<std::ptrdiff_t>(max_poses_));
    path_.poses.shrink_to_fit();
    path_.poses.reserve(max_poses_ + 1);  // the one allocation: push_back then erase never exceeds it
  }

  // Adds the pose; on every `every`-th one calls publish(const nav_msgs::Path&) (under the lock,
  // so the message is not changed while it is serialised).
  template <typename Publish>
  void add(const geometry_msgs::PoseStamped& pose, Publish&& publish) {
    std::lock_guard<std::mutex> lock(mutex_);
    path_.header = pose.header;
    path_.poses.push_back(pose);
    if (path_.poses.size() > max_poses_) path_.poses.erase(path_.poses.begin());
    if (++added_ % every_ == 0) publish(static_cast<const nav_msgs::Path&>(path_));
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    path_.poses.clear();  // keeps the reservation
  }
  size_t capacity() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return path_.poses.capacity();
  }

 private:
  mutable std::mutex mutex_;
  nav_msgs::Path path_;
  size_t max_poses_ = kDefaultMaxPoses;
  unsigned every_;
  unsigned long added_ = 0;
};

}  // namespace edge_slam
