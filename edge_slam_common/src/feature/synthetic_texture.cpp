#include "edge_slam/feature/synthetic_texture.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace edge_slam {

cv::Mat make_synthetic_texture(const cv::Size& size, uint64_t seed) {
  cv::Mat image;
  if (size.width <= 0 || size.height <= 0) return image;
  cv::RNG rng(seed);  // cv::RNG is a fixed multiply-with-carry generator: same on every platform

  // Smooth background: coarse uniform noise upsampled, so flat areas are not perfectly flat.
  cv::Mat coarse(std::max(2, size.height / 40), std::max(2, size.width / 40), CV_8UC1);
  rng.fill(coarse, cv::RNG::UNIFORM, 60, 200);
  cv::resize(coarse, image, size, 0, 0, cv::INTER_CUBIC);

  // Shapes from a few pixels to a sixth of the image, so every pyramid level sees corners.
  const int max_side = std::max(4, std::min(size.width, size.height) / 6);
  const int shapes = size.area() / 600;
  for (int i = 0; i < shapes; ++i) {
    const double t = rng.uniform(0.0, 1.0);
    const int extent = std::max(2, static_cast<int>(3 + (max_side - 3) * t * t * t));  // many small, few big
    const cv::Point center(rng.uniform(0, size.width), rng.uniform(0, size.height));
    const cv::Scalar gray(rng.uniform(0, 256));
    switch (rng.uniform(0, 3)) {
      case 0: {  // rotated rectangle
        const cv::RotatedRect box(center, cv::Size2f(extent, rng.uniform(extent / 3 + 1, extent + 1)),
                                  static_cast<float>(rng.uniform(0.0, 180.0)));
        cv::Point2f corners_f[4];
        box.points(corners_f);
        cv::Point corners[4];
        for (int k = 0; k < 4; ++k) corners[k] = cv::Point(cvRound(corners_f[k].x), cvRound(corners_f[k].y));
        cv::fillConvexPoly(image, corners, 4, gray, cv::LINE_AA);
        break;
      }
      case 1:
        cv::circle(image, center, extent / 2, gray, cv::FILLED, cv::LINE_AA);
        break;
      default: {  // triangle
        cv::Point corners[3];
        for (auto& p : corners) p = center + cv::Point(rng.uniform(-extent, extent + 1), rng.uniform(-extent, extent + 1));
        cv::fillConvexPoly(image, corners, 3, gray, cv::LINE_AA);
        break;
      }
    }
  }

  // Camera-like finish: slight blur, then a little sensor noise.
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.7);
  cv::Mat noise(size, CV_16SC1);
  rng.fill(noise, cv::RNG::NORMAL, 0, 3);
  cv::Mat noisy;
  image.convertTo(noisy, CV_16SC1);
  noisy += noise;
  noisy.convertTo(image, CV_8UC1);  // saturates to [0, 255]
  return image;
}

}  // namespace edge_slam
