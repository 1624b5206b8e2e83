#include "edge_slam/sim/ray_cast.h"

#include <cmath>
#include <limits>

namespace edge_slam {

RayHit cast_ray(const Scene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  static thread_local std::vector<int> all;
  if (all.size() != scene.boxes.size()) {
    all.resize(scene.boxes.size());
    for (size_t b = 0; b < all.size(); ++b) all[b] = static_cast<int>(b);
  }
  return cast_ray(scene, o, d, all);
}

RayHit cast_ray(const Scene& scene, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                const std::vector<int>& boxes) {
  RayHit best;
  best.t = std::numeric_limits<double>::infinity();
  double inv[3];
  for (int a = 0; a < 3; ++a) inv[a] = 1.0 / d[a];  // +-inf for axis-parallel rays is fine

  // Leaving the room: the nearest of the three faces the ray heads towards.
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) continue;
    const int side = d[a] > 0 ? 1 : 0;
    const double t = ((side ? scene.room.max[a] : scene.room.min[a]) - o[a]) * inv[a];
    if (t > 0 && t < best.t) {
      best.t = t;
      best.surface = scene.room_surface(a, side);
    }
  }
  // Entering a furniture box: slab test, the entry face is the axis with the latest entry.
  for (const int b : boxes) {
    const AlignedBox& box = scene.boxes[b];
    double t_near = -std::numeric_limits<double>::infinity();
    double t_far = std::numeric_limits<double>::infinity();
    int entry_axis = -1;
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0) {
        if (o[a] < box.min[a] || o[a] > box.max[a]) { t_far = -1; break; }
        continue;
      }
      double t0 = (box.min[a] - o[a]) * inv[a], t1 = (box.max[a] - o[a]) * inv[a];
      if (t0 > t1) std::swap(t0, t1);
      if (t0 > t_near) { t_near = t0; entry_axis = a; }
      if (t1 < t_far) t_far = t1;
    }
    if (entry_axis < 0 || t_near > t_far || t_near <= 0 || t_near >= best.t) continue;
    best.t = t_near;
    best.surface = scene.box_surface(b, entry_axis, d[entry_axis] > 0 ? 0 : 1);
  }
  return best;
}

double hit_depth(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  return cast_ray(scene, origin, dir).t;
}

namespace {
bool on_box_boundary(const AlignedBox& box, const Eigen::Vector3d& p, double tol) {
  if (!box.contains(p, tol)) return false;
  for (int a = 0; a < 3; ++a)
    if (std::abs(p[a] - box.min[a]) <= tol || std::abs(p[a] - box.max[a]) <= tol) return true;
  return false;
}
}  // namespace

bool on_surface(const Scene& scene, const Eigen::Vector3d& p, double tol) {
  if (on_box_boundary(scene.room, p, tol)) return true;
  for (const AlignedBox& box : scene.boxes)
    if (on_box_boundary(box, p, tol)) return true;
  return false;
}

}  // namespace edge_slam
