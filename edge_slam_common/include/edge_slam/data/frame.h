// A tracked image: shared feature data plus the per-frame tracking state (pose estimate,
// matched map points, outlier flags, BoW computed on demand, reference keyframe).
#pragma once
#include <Eigen/Geometry>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/data/bow_types.h"
#include "edge_slam/data/frame_features.h"

namespace edge_slam {

class BowVocabulary;
class KeyFrame;
class MapPoint;
class OrbExtractor;

// Validates an image pair against the calibration; throws std::invalid_argument with a
// message naming what is wrong (empty, type, size). Colour: CV_8UC1/CV_8UC3/CV_8UC4.
// Depth: CV_16UC1 or CV_32FC1 of the same size.
void validate_rgbd_input(const cv::Mat& color, const cv::Mat& depth, const PinholeCamera& camera);

// Converts an accepted colour image to CV_8UC1 into `gray`, whose buffer is written over when
// the size repeats (a 1-channel image is copied).
void to_gray_into(const cv::Mat& color, RgbEncoding encoding, cv::Mat& gray);

class Frame {
 public:
  Frame() = default;
  Frame(uint64_t id, double stamp, std::shared_ptr<const FrameFeatures> features);

  // Validates, converts to grey, extracts ORB, undistorts and samples depth.
  // Throws std::invalid_argument for bad input.
  static Frame from_rgbd(uint64_t id, double stamp, const cv::Mat& color, const cv::Mat& depth,
                         const PinholeCamera& camera, const OrbExtractor& extractor,
                         RgbEncoding encoding = RgbEncoding::kBgr);

  uint64_t id = 0;
  double stamp = 0;
  std::shared_ptr<const FrameFeatures> features;
  std::vector<std::shared_ptr<MapPoint>> map_points;  // per keypoint, null when unmatched
  std::vector<bool> outliers;                          // per keypoint, set by pose optimisation
  std::shared_ptr<KeyFrame> reference_kf;

  size_t size() const { return features ? features->size() : 0; }
  const FrameFeatures& feat() const { return *features; }

  void compute_bow(const BowVocabulary& vocabulary);  // no-op when already computed
  // Sets an already computed BoW (deserialisation, tests).
  void set_bow(BowVector bow, FeatureVector fv) {
    bow_ = std::move(bow);
    feature_vector_ = std::move(fv);
    has_bow_ = true;
  }
  bool has_bow() const { return has_bow_; }
  const BowVector& bow() const { return bow_; }
  const FeatureVector& feature_vector() const { return feature_vector_; }

  bool has_pose() const { return has_pose_; }
  void set_pose(const Eigen::Isometry3d& T_cw);
  const Eigen::Isometry3d& T_cw() const { return T_cw_; }
  Eigen::Isometry3d T_wc() const { return T_cw_.inverse(); }
  Eigen::Vector3d camera_center() const { return T_cw_.inverse().translation(); }

  std::vector<size_t> features_in_area(float x, float y, float r, int min_level = -1,
                                       int max_level = -1) const {
    std::vector<size_t> out;
    features->grid.in_area(x, y, r, min_level, max_level, out);
    return out;
  }
  // The same into a buffer the caller reuses across queries (no allocation per query).
  void features_in_area(float x, float y, float r, int min_level, int max_level, std::vector<size_t>& out) const {
    features->grid.in_area(x, y, r, min_level, max_level, out);
  }
  // World point of keypoint i from its depth and the current pose (depth must be valid).
  Eigen::Vector3d unproject_world(size_t i) const { return T_cw_.inverse() * features->unproject_camera(i); }

  int num_matched() const;  // non-null, non-outlier map points

 private:
  BowVector bow_;
  FeatureVector feature_vector_;
  bool has_bow_ = false;
  Eigen::Isometry3d T_cw_ = Eigen::Isometry3d::Identity();
  bool has_pose_ = false;
};

}  // namespace edge_slam
