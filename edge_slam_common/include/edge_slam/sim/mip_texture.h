// A colour texture with a mip-map pyramid and trilinear lookup. Sampling at the level that
// matches a pixel's footprint removes the aliasing that would make corners flicker from frame
// to frame as the camera moves.
#pragma once
#include <opencv2/core.hpp>
#include <vector>

namespace edge_slam {

class MipTexture {
 public:
  MipTexture() = default;
  // image: CV_8UC3 (BGR). Levels are halved (Gaussian pyrDown) down to ~4 texels.
  explicit MipTexture(const cv::Mat& image);

  // Trilinear colour (BGR, 0..255) at texel coordinates (x, y) of level 0; `level` is the
  // continuous mip level (0 = full resolution). Coordinates outside are clamped to the edge.
  cv::Vec3f sample(double x, double y, double level) const;

  int width() const { return levels_.empty() ? 0 : levels_[0].cols; }
  int height() const { return levels_.empty() ? 0 : levels_[0].rows; }
  int num_levels() const { return static_cast<int>(levels_.size()); }
  const cv::Mat& level(int i) const { return levels_[i]; }

 private:
  cv::Vec3f bilinear(int lvl, double x, double y) const;
  std::vector<cv::Mat> levels_;
};

}  // namespace edge_slam
