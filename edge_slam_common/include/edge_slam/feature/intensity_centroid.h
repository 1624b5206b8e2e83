// Keypoint orientation from the intensity centroid of a disc around it (Rosin's moments):
// the angle of the vector from the keypoint to the centroid of the patch brightness.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

// half_widths[v] = largest u with u^2 + v^2 <= radius^2, for v = 0..radius: the row
// extents of a digital disc. The disc is symmetric in u and v by construction.
std::vector<int> disc_half_widths(int radius);

// Angle in degrees, [0, 360), of the intensity centroid of the disc described by
// half_widths around pixel (x, y) of `image` (CV_8UC1). The caller guarantees the disc
// fits inside the image.
float intensity_centroid_angle(const cv::Mat& image, int x, int y, const std::vector<int>& half_widths);

// The same disc with per-row weight tables for a SIMD evaluation of the moments (radius <= 15,
// the ORB patch; larger discs use the scalar loop): identical integer moments, so the very
// same angle, in a fraction of the time (1000 keypoints a frame).
class CentroidDisc {
 public:
  explicit CentroidDisc(int radius);
  int radius() const { return radius_; }
  const std::vector<int>& half_widths() const { return half_widths_; }
  // As intensity_centroid_angle(image, x, y, half_widths()); the disc and the pixel left of
  // it must lie inside the image (the SIMD rows start at x - 16).
  float angle(const cv::Mat& image, int x, int y) const;

 private:
  static constexpr int kLanes = 32;  // u = -16 .. 15
  int radius_;
  std::vector<int> half_widths_;
  std::vector<int16_t> u_weight_;  // per row v: u inside the disc, 0 outside (kLanes each)
  std::vector<int16_t> inside_;    // per row v: 1 inside the disc, 0 outside
};

}  // namespace edge_slam
