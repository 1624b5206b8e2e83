// Plain, ROS-free records of what travels between the mobile and the edge. The map classes
// convert to/from these; the ROS bridge converts these to/from edge_slam_msgs. Keeping the
// wire contents here means the map <-> record code is testable without ROS, and the bridge
// stays a thin (de)quantisation + validation layer.
#pragma once
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include "edge_slam/util/ids.h"
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

namespace edge_slam {



// Camera reference sent with every KeyFrame/Frame: keypoints are already undistorted.
struct CameraRecord {
  std::string name;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double bf = 0;
  float th_depth = 0;  // metres
  int width = 0, height = 0;
};

// The features of a processed frame: undistorted keypoints, per-keypoint depth and descriptors.
struct FeatureRecord {
  std::vector<cv::KeyPoint> keypoints;  // pt = undistorted pixel, octave, angle (deg)
  std::vector<float> depth;             // metres; <= 0 means no valid depth
  cv::Mat descriptors;                  // N x 32, CV_8U
  size_t size() const { return keypoints.size(); }
};

struct NewPointRecord {
  uint32_t id = kNoId;
  uint32_t kp_index = 0;  // source keypoint: its descriptor is the point's descriptor
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
};

struct KeyFrameRecord {
  uint64_t seq = 0;
  uint32_t id = kNoId;
  uint32_t frame_id = kNoId;
  double stamp = 0;
  double created_wall = 0;  // mobile wall clock at creation (transmit latency)
  bool reset = false;
  Eigen::Isometry3d T_wc = Eigen::Isometry3d::Identity();  // camera pose in the map
  CameraRecord camera;
  FeatureRecord features;
  std::vector<std::pair<uint32_t, uint32_t>> observations;  // (keypoint index, map point id)
  std::vector<NewPointRecord> new_points;
  // The mobile's KeyFrame decision inputs (mobile -> edge), for conditions 1-2 on the edge.
  uint16_t tracked_points = 0, reference_points = 0, tracked_close_points = 0, untracked_close_points = 0;
  uint32_t parent_id = kNoId;                                // spanning tree
  std::vector<std::pair<uint32_t, uint32_t>> covisibility;   // (KeyFrame id, shared points)
  // Points on probation the mobile's tracking found too rarely (module/map_point_culling.h,
  // mobile -> edge; empty inside a MapUpdate): the edge culls them as ORB-SLAM2's tracker-fed
  // MapPointCulling would.
  std::vector<uint32_t> refuted_points;
};

struct FrameRecord {
  uint64_t seq = 0;
  uint32_t id = kNoId;
  double stamp = 0;
  double created_wall = 0;  // mobile wall clock when processed
  CameraRecord camera;
  FeatureRecord features;
};

struct MapPointRecord {
  uint32_t id = kNoId;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  std::array<uint8_t, 32> descriptor{};
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float min_distance = 0, max_distance = 0;
  uint32_t ref_keyframe_id = kNoId;
};

enum class MapUpdateKind : uint8_t { kPeriodic = 0, kRelocalization = 1 };

struct MapUpdateRecord {
  MapUpdateKind kind = MapUpdateKind::kPeriodic;
  uint64_t seq = 0;
  uint32_t request_frame_id = kNoId;
  double build_start = 0, publish_stamp = 0;  // edge clock, seconds
  uint64_t last_keyframe_seq = 0;             // acknowledgement of received KeyFrames
  std::vector<KeyFrameRecord> keyframes;
  std::vector<MapPointRecord> points;
};

}  // namespace edge_slam
