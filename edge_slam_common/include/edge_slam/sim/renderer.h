// Ray-traced RGB-D rendering of the synthetic room through an ideal pinhole camera.
#pragma once
#include "edge_slam/camera/pinhole_camera.h"
#include "edge_slam/sim/scene.h"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cstdint>

namespace edge_slam {

struct RenderOptions {
  int supersample = 2;     // colour rays per pixel = supersample^2 (anti-aliasing)
  double max_depth = 10.0; // metres; farther hits read 0 (no reading), like a Kinect
};

struct RenderedFrame {
  cv::Mat bgr;    // CV_8UC3, OpenCV's BGR channel order
  cv::Mat depth;  // CV_32FC1, z-depth in metres of the pixel-centre ray's first hit; 0 = none
};

// T_wc: camera (optical frame: x right, y down, z forward) to world. The camera's distortion
// coefficients must be zero (throws std::invalid_argument otherwise).
RenderedFrame render(const Scene& scene, const PinholeCamera& camera, const Eigen::Isometry3d& T_wc,
                     const RenderOptions& options = RenderOptions());

// Mild deterministic sensor noise: each channel gets an integer offset in [-2, 2] hashed from
// (seed, frame, pixel), so a frame is reproducible whatever order it is rendered in.
void add_sensor_noise(cv::Mat& bgr, uint64_t seed, uint64_t frame);

// Metres (CV_32F) -> TUM 16-bit depth (CV_16U, value = round(metres * factor); 0 stays 0,
// values beyond the 16-bit range become 0).
cv::Mat depth_to_tum16(const cv::Mat& depth_m, double factor = 5000.0);

}  // namespace edge_slam
