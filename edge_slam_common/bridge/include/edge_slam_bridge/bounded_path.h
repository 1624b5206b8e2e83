// The trajectory shown in rviz (nav_msgs/Path): the newest `max_poses` poses only, so the
// mobile's memory stays flat on long runs, published on every `every`-th pose (6 Hz at 30 fps
// is plenty for rviz). Thread-safe: the image callback adds, a service clears.
#pragma once
#include <nav_msgs/Path.h>
#include <ros/publisher.h>

#include <cstddef>
#include <mutex>

namespace edge_slam {

class BoundedPath {
 public:
  explicit BoundedPath(size_t max_poses = 20000, unsigned every = 5) : max_poses_(max_poses), every_(every) {}
  void set_max_poses(size_t max_poses) { max_poses_ = max_poses; }

  void add(const geometry_msgs::PoseStamped& pose, const ros::Publisher& publisher) {
    std::lock_guard<std::mutex> lock(mutex_);
    path_.header = pose.header;
    path_.poses.push_back(pose);
    if (path_.poses.size() > max_poses_) path_.poses.erase(path_.poses.begin());
    if (++added_ % every_ == 0) publisher.publish(path_);
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    path_.poses.clear();
  }

 private:
  std::mutex mutex_;
  nav_msgs::Path path_;
  size_t max_poses_;
  unsigned every_;
  unsigned long added_ = 0;
};

}  // namespace edge_slam
