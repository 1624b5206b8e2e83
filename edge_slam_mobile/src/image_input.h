// Camera input checks and conversion for the mobile: colour rgb8/bgr8/mono8 (any other
// encoding refused; bgr8 is converted to RGB), depth 16UC1 (camera depth_factor) or 32FC1
// metres, sizes matching the calibration, stamps strictly increasing, at least one valid depth
// value. A refusal says what was expected and which kind of problem it is (counted per kind on
// ~stats and the status). rgb8, mono8 and depth are read in place from the messages (cv_bridge's
// toCvShare) instead of copied: two VGA buffers less per frame on the mobile's heap.
#pragma once
#include <cv_bridge/cv_bridge.h>
#include <edge_slam/camera/pinhole_camera.h>
#include <edge_slam/split/image_problem.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgproc.hpp>
#include <string>

namespace edge_slam_mobile {

using edge_slam::ImageProblem;

struct ImageCheck {
  bool ok = false;
  ImageProblem problem = ImageProblem::kNone;
  std::string error;
  cv::Mat rgb;    // CV_8UC3 in RGB order, or CV_8UC1 (mono8)
  cv::Mat depth;  // CV_16UC1 (scaled by depth_factor) or CV_32FC1 metres, as received
  // What rgb and depth point into (the messages, or a converted copy): kept alive with them.
  cv_bridge::CvImageConstPtr rgb_source, depth_source;
};

// True at the first pixel holding a depth (non-zero; NaN and zero mean "no measurement"):
// a frame with depth stops at its first pixels, so no mask image is made.
inline bool has_valid_depth(const cv::Mat& depth) {
  for (int v = 0; v < depth.rows; ++v) {
    if (depth.type() == CV_16UC1) {
      const uint16_t* row = depth.ptr<uint16_t>(v);
      for (int u = 0; u < depth.cols; ++u)
        if (row[u] != 0) return true;
    } else {
      const float* row = depth.ptr<float>(v);
      for (int u = 0; u < depth.cols; ++u)
        if (row[u] > 0.f) return true;  // NaN > 0 is false
    }
  }
  return false;
}

inline ImageCheck convert_rgbd(const sensor_msgs::ImageConstPtr& rgb_msg, const sensor_msgs::ImageConstPtr& depth_msg,
                               const edge_slam::PinholeCamera& camera, const ros::Time& last_stamp) {
  const sensor_msgs::Image& rgb = *rgb_msg;
  const sensor_msgs::Image& depth = *depth_msg;
  namespace enc = sensor_msgs::image_encodings;
  ImageCheck c;
  if (!last_stamp.isZero() && rgb.header.stamp <= last_stamp) {
    c.error = "colour stamp " + std::to_string(rgb.header.stamp.toSec()) + " is not after the previous frame's " +
              std::to_string(last_stamp.toSec()) + " (out-of-order or repeated frame)";
    c.problem = ImageProblem::kStamp;
    return c;
  }
  if (rgb.encoding != enc::RGB8 && rgb.encoding != enc::BGR8 && rgb.encoding != enc::MONO8) {
    c.error = "colour encoding '" + rgb.encoding + "', expected rgb8, bgr8 or mono8";
    c.problem = ImageProblem::kEncoding;
    return c;
  }
  if (depth.encoding != enc::TYPE_16UC1 && depth.encoding != enc::MONO16 && depth.encoding != enc::TYPE_32FC1) {
    c.error = "depth encoding '" + depth.encoding + "', expected 16UC1 (x depth_factor) or 32FC1 (metres)";
    c.problem = ImageProblem::kEncoding;
    return c;
  }
  const int w = camera.width, h = camera.height;
  c.problem = ImageProblem::kSize;
  if (rgb.width != depth.width || rgb.height != depth.height) {
    c.error = "colour is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) + " but depth is " +
              std::to_string(depth.width) + "x" + std::to_string(depth.height) + " (expected the same size)";
    return c;
  }
  if (static_cast<int>(rgb.width) != w || static_cast<int>(rgb.height) != h ||
      static_cast<int>(depth.width) != w || static_cast<int>(depth.height) != h) {
    c.error = "image sizes colour " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) + ", depth " +
              std::to_string(depth.width) + "x" + std::to_string(depth.height) + ", expected " + std::to_string(w) +
              "x" + std::to_string(h) + " (camera '" + camera.name + "')";
    return c;
  }
  // cv_bridge trusts step and the buffer length: a short buffer would be read past its end.
  for (const sensor_msgs::Image* im : {&rgb, &depth}) {
    const size_t row = static_cast<size_t>(im->width) * enc::numChannels(im->encoding) * (enc::bitDepth(im->encoding) / 8);
    if (im->step < row || im->data.size() < static_cast<size_t>(im->step) * im->height) {
      c.error = "image '" + im->encoding + "' has step " + std::to_string(im->step) + " and " +
                std::to_string(im->data.size()) + " bytes, expected step >= " + std::to_string(row) + " and " +
                "step x height bytes";
      return c;
    }
  }
  try {
    c.rgb_source = cv_bridge::toCvShare(rgb_msg, rgb.encoding == enc::MONO8 ? enc::MONO8 : enc::RGB8);
    c.rgb = c.rgb_source->image;
  } catch (const cv_bridge::Exception& e) {
    c.error = std::string("colour conversion failed: ") + e.what();
    c.problem = ImageProblem::kEncoding;
    return c;
  }
  c.problem = ImageProblem::kDepth;
  try {
    c.depth_source = cv_bridge::toCvShare(depth_msg);
    c.depth = c.depth_source->image;
  } catch (const cv_bridge::Exception& e) {
    c.error = std::string("depth conversion failed: ") + e.what();
    return c;
  }
  // A frame without depth cannot be tracked as RGB-D (sensor dropout, wrong topic): NaN and
  // zero both mean "no measurement" (NaN > 0 is false).
  if (!has_valid_depth(c.depth)) {
    c.error = "depth image holds no valid value (all zero or NaN)";
    return c;
  }
  c.problem = ImageProblem::kNone;
  c.ok = true;
  return c;
}

}  // namespace edge_slam_mobile
