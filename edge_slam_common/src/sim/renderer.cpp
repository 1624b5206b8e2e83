// Per pixel: one ray through the pixel centre gives the exact z-depth; supersample^2 jittered-free
// grid rays give the anti-aliased colour. Texture lookups pick the mip level matching each
// sample's footprint on the surface, so distant and oblique texture does not shimmer.
#include "edge_slam/sim/renderer.h"

#include "edge_slam/sim/random.h"
#include "edge_slam/sim/ray_cast.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace edge_slam {
namespace {

// Lambertian light from the ceiling lamp plus ambient light, on the surface's albedo.
float shading(const Scene& scene, const Surface& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d to_light = scene.light_position - p;
  const double d2 = to_light.squaredNorm();
  const double lambert = std::max(0.0, s.normal.dot(to_light) / std::sqrt(d2));
  return static_cast<float>(s.albedo_gain * (0.55 + 1.1 * lambert / (1.0 + 0.12 * d2)));
}

cv::Vec3f shade_sample(const Scene& scene, const std::vector<int>& boxes, const Eigen::Vector3d& o,
                       const Eigen::Vector3d& d, double pixel_angle) {
  const RayHit hit = cast_ray(scene, o, d, boxes);
  if (!hit.hit()) return cv::Vec3f(0, 0, 0);
  const Surface& s = scene.surfaces[hit.surface];
  const Eigen::Vector3d p = o + hit.t * d;
  const double dist = hit.t * d.norm();
  const double cos_incidence = std::max(0.05, std::abs(s.normal.dot(d)) / d.norm());
  // Footprint (texels) of this sample: isotropic part times the geometric mean of the
  // oblique stretch, a compromise between blur and aliasing at grazing angles.
  const double footprint = dist * pixel_angle * s.texels_per_m / std::sqrt(cos_incidence);
  const double level = footprint > 1.0 ? std::log2(footprint) : 0.0;
  const double tx = (p[s.u_axis] - s.origin[s.u_axis]) * s.texels_per_m;
  const double ty = (p[s.v_axis] - s.origin[s.v_axis]) * s.texels_per_m;
  return s.texture.sample(tx, ty, level) * shading(scene, s, p);
}

// Furniture boxes that may appear in the image: a box is dropped when all its corners are on
// the outer side of one frustum plane (with a pixel of margin). Only a speed-up: exact either way.
std::vector<int> boxes_in_view(const Scene& scene, const PinholeCamera& cam, const Eigen::Isometry3d& T_wc) {
  const Eigen::Isometry3d T_cw = T_wc.inverse();
  const double x_lo = (-2 - cam.cx) / cam.fx, x_hi = (cam.width + 1 - cam.cx) / cam.fx;
  const double y_lo = (-2 - cam.cy) / cam.fy, y_hi = (cam.height + 1 - cam.cy) / cam.fy;
  std::vector<int> visible;
  for (size_t b = 0; b < scene.boxes.size(); ++b) {
    const AlignedBox& box = scene.boxes[b];
    bool outside[5] = {true, true, true, true, true};
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d corner((k & 1) ? box.max.x() : box.min.x(), (k & 2) ? box.max.y() : box.min.y(),
                                   (k & 4) ? box.max.z() : box.min.z());
      const Eigen::Vector3d p = T_cw * corner;
      outside[0] &= p.z() <= 0;
      outside[1] &= p.x() < x_lo * p.z();
      outside[2] &= p.x() > x_hi * p.z();
      outside[3] &= p.y() < y_lo * p.z();
      outside[4] &= p.y() > y_hi * p.z();
    }
    if (!(outside[0] || outside[1] || outside[2] || outside[3] || outside[4]))
      visible.push_back(static_cast<int>(b));
  }
  return visible;
}

}  // namespace

RenderedFrame render(const Scene& scene, const PinholeCamera& cam, const Eigen::Isometry3d& T_wc,
                     const RenderOptions& opt) {
  if (cam.has_distortion()) throw std::invalid_argument("render: camera must have no distortion");
  if (cam.width <= 0 || cam.height <= 0 || cam.fx <= 0 || cam.fy <= 0)
    throw std::invalid_argument("render: invalid camera intrinsics");
  const int ss = std::max(1, opt.supersample);
  RenderedFrame out;
  out.bgr.create(cam.height, cam.width, CV_8UC3);
  out.depth.create(cam.height, cam.width, CV_32FC1);
  const Eigen::Matrix3d R = T_wc.linear();
  const Eigen::Vector3d o = T_wc.translation();
  const double pixel_angle = 1.0 / (std::sqrt(cam.fx * cam.fy) * ss);
  const float inv_n = 1.0f / static_cast<float>(ss * ss);
  const std::vector<int> boxes = boxes_in_view(scene, cam, T_wc);

  for (int v = 0; v < cam.height; ++v) {
    cv::Vec3b* rgb_row = out.bgr.ptr<cv::Vec3b>(v);
    float* depth_row = out.depth.ptr<float>(v);
    for (int u = 0; u < cam.width; ++u) {
      // z-depth: with a camera-frame direction whose z is 1, the ray parameter is the depth.
      const Eigen::Vector3d d_centre = R * Eigen::Vector3d((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      const double z = cast_ray(scene, o, d_centre, boxes).t;
      depth_row[u] = (std::isfinite(z) && z <= opt.max_depth) ? static_cast<float>(z) : 0.0f;

      cv::Vec3f sum(0, 0, 0);
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          const double su = u - 0.5 + (sx + 0.5) / ss, sv = v - 0.5 + (sy + 0.5) / ss;
          const Eigen::Vector3d d = R * Eigen::Vector3d((su - cam.cx) / cam.fx, (sv - cam.cy) / cam.fy, 1.0);
          sum += shade_sample(scene, boxes, o, d, pixel_angle);
        }
      sum *= inv_n;
      rgb_row[u] = cv::Vec3b(cv::saturate_cast<uchar>(sum[0]), cv::saturate_cast<uchar>(sum[1]),
                             cv::saturate_cast<uchar>(sum[2]));
    }
  }
  return out;
}

void add_sensor_noise(cv::Mat& bgr, uint64_t seed, uint64_t frame) {
  for (int v = 0; v < bgr.rows; ++v) {
    cv::Vec3b* row = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < bgr.cols; ++u) {
      uint64_t h = hash_mix(seed, frame, static_cast<uint64_t>(v) * 65536u + u);
      for (int c = 0; c < 3; ++c, h >>= 8) {
        // Sum of two 0..2 values minus 2: triangular distribution on [-2, 2].
        const int noise = static_cast<int>(h % 3) + static_cast<int>((h >> 4) % 3) - 2;
        row[u][c] = cv::saturate_cast<uchar>(row[u][c] + noise);
      }
    }
  }
}

cv::Mat depth_to_tum16(const cv::Mat& depth_m, double factor) {
  CV_Assert(depth_m.type() == CV_32FC1);
  cv::Mat out(depth_m.size(), CV_16UC1);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* in = depth_m.ptr<float>(v);
    uint16_t* o = out.ptr<uint16_t>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      const double raw = std::round(in[u] * factor);
      o[u] = (in[u] > 0 && raw <= 65535.0) ? static_cast<uint16_t>(raw) : 0;
    }
  }
  return out;
}

}  // namespace edge_slam
