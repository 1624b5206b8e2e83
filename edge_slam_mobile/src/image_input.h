// Camera input checks and conversion for the mobile: colour rgb8/bgr8/mono8 (any other
// encoding refused) to RGB, depth 16UC1 (camera depth_factor) or 32FC1 metres, sizes matching
// the calibration, stamps strictly increasing. A refusal says what was expected.
#pragma once
#include <cv_bridge/cv_bridge.h>
#include <edge_slam/camera/pinhole_camera.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgproc.hpp>
#include <string>

namespace edge_slam_mobile {

struct ImageCheck {
  bool ok = false;
  std::string error;
  cv::Mat rgb;    // CV_8UC3, RGB order
  cv::Mat depth;  // CV_16UC1 (scaled by depth_factor) or CV_32FC1 metres, as received
};

inline ImageCheck convert_rgbd(const sensor_msgs::Image& rgb, const sensor_msgs::Image& depth,
                               const edge_slam::PinholeCamera& camera, const ros::Time& last_stamp) {
  namespace enc = sensor_msgs::image_encodings;
  ImageCheck c;
  if (!last_stamp.isZero() && rgb.header.stamp <= last_stamp) {
    c.error = "colour stamp " + std::to_string(rgb.header.stamp.toSec()) + " is not after the previous frame's " +
              std::to_string(last_stamp.toSec()) + " (out-of-order or repeated frame)";
    return c;
  }
  if (rgb.encoding != enc::RGB8 && rgb.encoding != enc::BGR8 && rgb.encoding != enc::MONO8) {
    c.error = "colour encoding '" + rgb.encoding + "', expected rgb8, bgr8 or mono8";
    return c;
  }
  if (depth.encoding != enc::TYPE_16UC1 && depth.encoding != enc::MONO16 && depth.encoding != enc::TYPE_32FC1) {
    c.error = "depth encoding '" + depth.encoding + "', expected 16UC1 (x depth_factor) or 32FC1 (metres)";
    return c;
  }
  const int w = camera.width, h = camera.height;
  if (static_cast<int>(rgb.width) != w || static_cast<int>(rgb.height) != h ||
      static_cast<int>(depth.width) != w || static_cast<int>(depth.height) != h) {
    c.error = "image sizes colour " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) + ", depth " +
              std::to_string(depth.width) + "x" + std::to_string(depth.height) + ", expected " + std::to_string(w) +
              "x" + std::to_string(h) + " (camera '" + camera.name + "')";
    return c;
  }
  try {
    c.rgb = cv_bridge::toCvCopy(rgb, enc::RGB8)->image;
    c.depth = cv_bridge::toCvCopy(depth)->image;
  } catch (const cv_bridge::Exception& e) {
    c.error = std::string("image conversion failed: ") + e.what();
    return c;
  }
  c.ok = true;
  return c;
}

}  // namespace edge_slam_mobile
