#include "edge_slam/data/frame.h"

#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/map_point.h"
#include "edge_slam/feature/orb_extractor.h"

namespace edge_slam {

namespace {
// ORB-SLAM2 transforms BoW with the feature vector taken 4 levels above the leaves.
constexpr int kBowLevelsUp = 4;

std::string size_text(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}
}  // namespace

void validate_rgbd_input(const cv::Mat& color, const cv::Mat& depth, const PinholeCamera& camera) {
  if (color.empty()) throw std::invalid_argument("frame: colour image is empty");
  if (color.depth() != CV_8U || (color.channels() != 1 && color.channels() != 3 && color.channels() != 4))
    throw std::invalid_argument("frame: colour image must be 8-bit with 1, 3 or 4 channels (got type " +
                                std::to_string(color.type()) + ")");
  if (color.cols != camera.width || color.rows != camera.height)
    throw std::invalid_argument("frame: colour image is " + size_text(color) +
                                " but the calibration '" + camera.name + "' is " +
                                std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (depth.empty()) throw std::invalid_argument("frame: depth image is empty");
  if (depth.type() != CV_16UC1 && depth.type() != CV_32FC1)
    throw std::invalid_argument("frame: depth image must be CV_16UC1 or CV_32FC1 (got type " +
                                std::to_string(depth.type()) + ")");
  if (depth.size() != color.size())
    throw std::invalid_argument("frame: depth image is " + size_text(depth) +
                                " but the colour image is " + size_text(color));
}

void to_gray_into(const cv::Mat& color, RgbEncoding encoding, cv::Mat& gray) {
  const bool rgb = encoding == RgbEncoding::kRgb;
  switch (color.channels()) {
    case 1: color.copyTo(gray); break;
    case 3: cv::cvtColor(color, gray, rgb ? cv::COLOR_RGB2GRAY : cv::COLOR_BGR2GRAY); break;
    case 4: cv::cvtColor(color, gray, rgb ? cv::COLOR_RGBA2GRAY : cv::COLOR_BGRA2GRAY); break;
    default: throw std::invalid_argument("frame: unsupported channel count");
  }
}

Frame::Frame(uint64_t frame_id, double frame_stamp, std::shared_ptr<const FrameFeatures> f)
    : id(frame_id), stamp(frame_stamp), features(std::move(f)) {
  map_points.assign(size(), nullptr);
  outliers.assign(size(), false);
}

Frame Frame::from_rgbd(uint64_t id, double stamp, const cv::Mat& color, const cv::Mat& depth,
                       const PinholeCamera& camera, const OrbExtractor& extractor,
                       RgbEncoding encoding) {
  validate_rgbd_input(color, depth, camera);
  // The grey image goes into a buffer the tracking thread keeps from frame to frame (as the
  // extractor keeps its pyramid, orb_extractor.cpp): one VGA allocation less per frame.
  thread_local cv::Mat gray_buffer;
  cv::Mat gray;
  if (color.channels() == 1) {
    gray = color;  // the caller's image itself: never written into
  } else {
    to_gray_into(color, encoding, gray_buffer);
    gray = gray_buffer;
  }
  std::vector<cv::KeyPoint> keys;
  cv::Mat desc;
  extractor.extract(gray, keys, desc);
  auto pyramid = std::make_shared<ScalePyramid>(
      ScalePyramid::make(extractor.num_levels(), extractor.scale_factor()));
  return Frame(id, stamp, FrameFeatures::build(camera, pyramid, std::move(keys), desc, depth));
}

void Frame::compute_bow(const BowVocabulary& vocabulary) {
  if (has_bow_) return;
  vocabulary.transform(features->descriptors, bow_, feature_vector_, kBowLevelsUp);
  has_bow_ = true;
}

void Frame::set_pose(const Eigen::Isometry3d& T_cw) {
  T_cw_ = T_cw;
  has_pose_ = true;
}

int Frame::num_matched() const {
  int n = 0;
  for (size_t i = 0; i < map_points.size(); ++i)
    if (map_points[i] && !outliers[i]) ++n;
  return n;
}

}  // namespace edge_slam
