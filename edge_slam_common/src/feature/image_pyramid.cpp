#include "edge_slam/feature/image_pyramid.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

namespace edge_slam {

std::vector<cv::Mat> build_image_pyramid(const cv::Mat& gray, const std::vector<float>& inv_scale_factors) {
  std::vector<cv::Mat> levels;
  build_image_pyramid_into(gray, inv_scale_factors, levels);
  return levels;
}

void build_image_pyramid_into(const cv::Mat& gray, const std::vector<float>& inv_scale_factors,
                              std::vector<cv::Mat>& levels) {
  levels.resize(inv_scale_factors.size());
  if (levels.empty()) return;
  levels[0] = gray;
  for (size_t n = 1; n < levels.size(); ++n) {
    const cv::Size size(static_cast<int>(std::lround(gray.cols * inv_scale_factors[n])),
                        static_cast<int>(std::lround(gray.rows * inv_scale_factors[n])));
    if (gray.empty() || size.width < 1 || size.height < 1 || levels[n - 1].empty()) {
      levels[n].release();
      continue;
    }
    cv::resize(levels[n - 1], levels[n], size, 0, 0, cv::INTER_LINEAR);  // reuses levels[n]'s buffer
  }
}

}  // namespace edge_slam
