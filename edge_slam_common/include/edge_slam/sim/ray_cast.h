// Exact ray casting against the synthetic room: the ground-truth geometry behind rendered depth.
#pragma once
#include "edge_slam/sim/scene.h"

#include <Eigen/Core>

#include <vector>

namespace edge_slam {

struct RayHit {
  double t = 0;      // ray parameter: hit point = origin + t * dir (t = distance if |dir| = 1)
  int surface = -1;  // index into Scene::surfaces, -1 if nothing was hit
  bool hit() const { return surface >= 0; }
};

// First surface hit by origin + t * dir, t > 0. dir need not be unit length. An origin
// inside a furniture box ignores that box (it only matters to the room's faces then).
RayHit cast_ray(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir);

// Same, testing only the listed furniture boxes (e.g. those inside a view frustum).
RayHit cast_ray(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                const std::vector<int>& boxes);

// Shorthand: the ray parameter of the first hit, +infinity when nothing is hit.
double hit_depth(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir);

// True when p lies on some surface of the scene within tol metres (for checking depth maps).
bool on_surface(const Scene& scene, const Eigen::Vector3d& p, double tol);

}  // namespace edge_slam
