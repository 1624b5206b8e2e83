// The synthetic room: an axis-aligned box room (world frame: z up, floor at z = 0, origin at the
// floor centre) furnished with axis-aligned boxes. Every face of the room and of each box is a
// Surface with its own procedural texture. Geometry is exact, so ray casts give ground truth.
#pragma once
#include "edge_slam/sim/mip_texture.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace edge_slam {

struct AlignedBox {
  Eigen::Vector3d min, max;
  bool contains(const Eigen::Vector3d& p, double margin = 0) const {
    return (p.array() > min.array() - margin).all() && (p.array() < max.array() + margin).all();
  }
};

// One planar face, perpendicular to world axis `axis`. Texture column = (p[u_axis] -
// origin[u_axis]) * texels_per_m, row likewise along v_axis.
struct Surface {
  int axis = 0;
  int u_axis = 1, v_axis = 2;
  Eigen::Vector3d normal;   // facing the free space the camera is in
  Eigen::Vector3d origin;   // texture (0, 0) corner
  double albedo_gain = 1;   // per-face brightness so that faces of a box differ
  double texels_per_m = 256;
  MipTexture texture;
  std::string name;
};

struct Scene {
  uint64_t seed = 0;
  AlignedBox room;                 // the camera is inside; its faces look inward
  std::vector<AlignedBox> boxes;   // furniture, faces look outward
  // surfaces[2*axis + side] are the room's faces (side 0 = min face); box b's faces start at
  // 6 + 6*b with the same ordering.
  std::vector<Surface> surfaces;
  double texels_per_m = 256;
  Eigen::Vector3d light_position;  // a ceiling lamp for Lambertian shading

  // Deterministic in seed. texels_per_m trades texture detail for memory/generation time.
  static Scene build(uint64_t seed, double texels_per_m = 256);

  int room_surface(int axis, int side) const { return 2 * axis + side; }
  int box_surface(int box, int axis, int side) const { return 6 + 6 * box + 2 * axis + side; }
};

}  // namespace edge_slam
