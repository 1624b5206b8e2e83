// Reader of TUM RGB-D benchmark folders (rgb.txt, depth.txt, groundtruth.txt, rgb/, depth/):
// colour/depth association by nearest timestamp, ground truth, and on-demand image loading.
// Every error is a std::runtime_error naming the file (and line, for text files).
#pragma once
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <string>
#include <utility>
#include <vector>

namespace edge_slam {

// One `timestamp filename` line of rgb.txt or depth.txt (path relative to the folder).
struct TumListEntry {
  double stamp = 0;
  std::string path;
};

// An associated colour/depth pair. Paths are full (folder + relative path).
struct TumFrame {
  double rgb_stamp = 0, depth_stamp = 0;
  std::string rgb_path, depth_path;
};

using StampedPose = std::pair<double, Eigen::Isometry3d>;

// Parses rgb.txt / depth.txt style lists: '#' comments and blank lines skipped; entries sorted
// by time. Throws "file:line: ..." on a malformed line.
std::vector<TumListEntry> read_tum_list(const std::string& path);

// Parses groundtruth.txt: `timestamp tx ty tz qx qy qz qw` (quaternion normalised).
std::vector<StampedPose> read_tum_ground_truth(const std::string& path);

// Pairs each colour entry with the nearest depth entry within max_dt seconds, greedily by
// smallest time difference, each depth used at most once (as TUM's associate.py does).
// Result sorted by colour stamp; elements are (rgb index, depth index).
std::vector<std::pair<size_t, size_t>> associate_by_stamp(const std::vector<TumListEntry>& rgb,
                                                          const std::vector<TumListEntry>& depth,
                                                          double max_dt);

class TumDataset {
 public:
  // Reads the lists and (if present) groundtruth.txt; images are loaded on demand.
  static TumDataset open(const std::string& folder, double max_dt = 0.02);

  const std::vector<TumFrame>& frames() const { return frames_; }
  size_t size() const { return frames_.size(); }
  // Empty when the folder has no groundtruth.txt (e.g. the benchmark's validation sequences).
  const std::vector<StampedPose>& ground_truth() const { return ground_truth_; }
  // Every line of rgb.txt / depth.txt, associated or not.
  const std::vector<TumListEntry>& rgb_list() const { return rgb_list_; }
  const std::vector<TumListEntry>& depth_list() const { return depth_list_; }
  const std::string& folder() const { return folder_; }

  // Colour as cv::imread gives it: CV_8UC3, BGR (.png or .jpg).
  cv::Mat load_rgb(size_t i) const;
  // Raw depth: CV_16UC1 (throws if the PNG is anything else).
  cv::Mat load_depth(size_t i) const;
  // Depth in metres (CV_32FC1, raw / depth_factor; 0 = no reading).
  cv::Mat load_depth_metres(size_t i, double depth_factor = 5000.0) const;

 private:
  std::string folder_;
  std::vector<TumListEntry> rgb_list_, depth_list_;
  std::vector<TumFrame> frames_;
  std::vector<StampedPose> ground_truth_;
};

}  // namespace edge_slam
