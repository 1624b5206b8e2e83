#include "edge_slam/feature/orb_extractor.h"

#include <opencv2/imgproc.hpp>
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "edge_slam/feature/descriptor_distance.h"
#include "edge_slam/feature/fast_grid_detector.h"
#include "edge_slam/feature/image_pyramid.h"
#include "edge_slam/feature/intensity_centroid.h"
#include "edge_slam/feature/orb_patch.h"
#include "edge_slam/feature/quadtree_distribution.h"
#include "edge_slam/feature/rotated_brief.h"

namespace edge_slam {
namespace {

// Smoothing before the binary tests; 7x7 with sigma 2 as in the ORB paper's setup.
void smooth_for_descriptor(const cv::Mat& level_image, cv::Mat& smoothed) {
  cv::GaussianBlur(level_image, smoothed, cv::Size(7, 7), 2.0, 2.0, cv::BORDER_REFLECT_101);
}

// The pyramid and its smoothed levels, about 1.6 MB per VGA frame, kept from one frame to the
// next by the thread that extracts (one per thread, so extract() stays const and thread-safe).
// Allocated afresh each frame they were most of the mobile's large per-frame allocations, and
// glibc's heap, which serves them once its mmap threshold has grown past them, fragments
// around them: the mobile's RSS crept by ~1 MB/min on the long run with a constant Local-Map.
struct ExtractionBuffers {
  std::vector<cv::Mat> pyramid;
  std::vector<cv::Mat> smoothed;
};

}  // namespace

OrbExtractor::OrbExtractor(const OrbParams& params) : params_(params), disc_(kOrbPatchRadius) {
  validate_orb_params(params_);
  scales_ = make_pyramid_scales(params_.scale_factor, params_.num_levels);
  features_per_level_ = edge_slam::features_per_level(params_.num_features, params_.scale_factor, params_.num_levels);
}

void OrbExtractor::extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const {
  keypoints.clear();
  descriptors = cv::Mat(0, kDescriptorBytes, CV_8U);
  if (gray.empty()) return;
  if (gray.type() != CV_8UC1)
    throw std::invalid_argument("OrbExtractor::extract: expected a CV_8UC1 image, got type " +
                                std::to_string(gray.type()));

  thread_local ExtractionBuffers buffers;
  build_image_pyramid_into(gray, scales_.inv_scale, buffers.pyramid);
  const std::vector<cv::Mat>& pyramid = buffers.pyramid;
  buffers.smoothed.resize(pyramid.size());
  FastGridParams fast;
  fast.cell_size = kOrbFastCellSize;
  fast.border = kOrbEdgeBorder;
  fast.ini_threshold = params_.ini_fast_threshold;
  fast.min_threshold = params_.min_fast_threshold;

  std::vector<uint8_t> descriptor_bytes;
  for (int level = 0; level < params_.num_levels; ++level) {
    const cv::Mat& image = pyramid[level];
    if (image.empty() || features_per_level_[level] == 0) continue;
    const cv::Rect area = fast_detection_area(image.size(), kOrbEdgeBorder);
    if (area.empty()) continue;

    std::vector<cv::KeyPoint> level_keypoints =
        distribute_quadtree(detect_fast_in_grid(image, fast), cv::Rect2f(area), features_per_level_[level]);
    if (level_keypoints.empty()) continue;
    // In row order: a message codes each y as the difference from the previous keypoint's
    // (io/keypoint_coding.h), ~8 bits instead of 16. Nothing else depends on the order.
    std::sort(level_keypoints.begin(), level_keypoints.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
      return a.pt.y != b.pt.y ? a.pt.y < b.pt.y : a.pt.x < b.pt.x;
    });

    cv::Mat& smoothed = buffers.smoothed[level];
    smooth_for_descriptor(image, smoothed);
    // Level pixel centres map to full resolution through the actual (rounded) level size.
    const float to_full_x = static_cast<float>(gray.cols) / image.cols;
    const float to_full_y = static_cast<float>(gray.rows) / image.rows;
    const size_t first_byte = descriptor_bytes.size();
    descriptor_bytes.resize(first_byte + level_keypoints.size() * kDescriptorBytes);
    uint8_t* out = descriptor_bytes.data() + first_byte;
    for (cv::KeyPoint kp : level_keypoints) {
      const int x = cvRound(kp.pt.x);
      const int y = cvRound(kp.pt.y);
      kp.angle = disc_.angle(image, x, y);
      compute_rotated_brief(smoothed, x, y, kp.angle, out);
      out += kDescriptorBytes;
      kp.octave = level;
      kp.size = kOrbPatchSize * scales_.scale[level];
      kp.pt.x = (kp.pt.x + 0.5f) * to_full_x - 0.5f;
      kp.pt.y = (kp.pt.y + 0.5f) * to_full_y - 0.5f;
      keypoints.push_back(kp);
    }
  }
  if (!buffers.pyramid.empty()) buffers.pyramid.front().release();  // the caller's image, not ours to keep
  if (keypoints.empty()) return;
  descriptors = cv::Mat(static_cast<int>(keypoints.size()), kDescriptorBytes, CV_8U);
  std::memcpy(descriptors.data, descriptor_bytes.data(), descriptor_bytes.size());
}

}  // namespace edge_slam
