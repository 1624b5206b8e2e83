// Room layout: 8 x 6 x 3 m. Furniture sits against the walls (each box has |x| >= 3.05 or
// |y| >= 2.2 everywhere) so the camera's loop around the middle stays >= 0.8 m clear of it.
// The seed jitters furniture positions and paints every texture.
#include "edge_slam/sim/scene.h"

#include "edge_slam/sim/random.h"
#include "edge_slam/sim/texture_painter.h"

#include <cmath>

namespace edge_slam {
namespace {

AlignedBox make_box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return AlignedBox{Eigen::Vector3d(x0, y0, z0), Eigen::Vector3d(x1, y1, z1)};
}

// Furniture against the walls; jitter slides items along their wall only.
std::vector<AlignedBox> furniture(SplitMix64& rng) {
  auto j = [&](double amount) { return rng.uniform(-amount, amount); };
  std::vector<AlignedBox> b;
  double s = j(0.4);
  b.push_back(make_box(3.55, -1.6 + s, 0.0, 4.0, 0.3 + s, 2.1));        // bookshelf, +x wall
  s = j(0.3);
  b.push_back(make_box(-2.6 + s, 2.45, 0.0, -0.9 + s, 3.0, 0.9));       // cabinet, +y wall
  b.push_back(make_box(-2.2 + s, 2.6, 0.9, -1.5 + s, 2.95, 1.35));      // box on the cabinet
  s = j(0.3);
  b.push_back(make_box(-3.95, -1.0 + s, 0.0, -3.05, 0.7 + s, 0.75));    // desk block, -x wall
  b.push_back(make_box(-4.0, -3.0, 0.0, -3.2, -2.2, 2.2));              // wardrobe, corner
  s = j(0.4);
  b.push_back(make_box(0.4 + s, -3.0, 0.0, 2.5 + s, -2.2, 0.8));        // sofa block, -y wall
  b.push_back(make_box(3.2, 2.2, 0.0, 3.95, 2.95, 0.6));                // crate, corner
  s = j(0.4);
  b.push_back(make_box(0.6 + s, 2.94, 1.1, 1.9 + s, 3.0, 2.0));         // framed picture, +y wall
  s = j(0.3);
  b.push_back(make_box(-3.97, 1.4 + s, 1.0, -3.9, 2.4 + s, 1.8));       // whiteboard, -x wall
  b.push_back(make_box(3.6, -2.9, 0.0, 3.95, -2.3, 1.1));               // side cabinet, +x/-y
  return b;
}

Surface make_surface(int axis, int side, bool inward, const AlignedBox& box) {
  Surface s;
  s.axis = axis;
  s.u_axis = axis == 0 ? 1 : 0;
  s.v_axis = axis == 2 ? 1 : 2;
  s.normal = Eigen::Vector3d::Zero();
  const double outward = side == 0 ? -1.0 : 1.0;
  s.normal[axis] = inward ? -outward : outward;
  s.origin = box.min;
  s.origin[axis] = side == 0 ? box.min[axis] : box.max[axis];
  return s;
}

}  // namespace

Scene Scene::build(uint64_t seed, double texels_per_m) {
  Scene scene;
  scene.seed = seed;
  scene.texels_per_m = texels_per_m;
  scene.room = make_box(-4.0, -3.0, 0.0, 4.0, 3.0, 3.0);
  scene.light_position = Eigen::Vector3d(0.3, -0.2, 2.9);
  SplitMix64 rng(seed);
  SplitMix64 layout_rng = rng.fork();
  scene.boxes = furniture(layout_rng);

  const char* axis_names = "xyz";
  auto add_faces = [&](const AlignedBox& box, bool inward, const std::string& prefix) {
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        Surface s = make_surface(axis, side, inward, box);
        const Eigen::Vector3d ext = box.max - box.min;
        SurfaceStyle style = inward ? SurfaceStyle::kWall : SurfaceStyle::kFurniture;
        if (inward && axis == 2) style = side == 0 ? SurfaceStyle::kFloor : SurfaceStyle::kCeiling;
        SplitMix64 paint_rng = rng.fork();
        const bool hidden_bottom = !inward && axis == 2 && side == 0;
        // A box's underside is never seen: keep its texture tiny.
        const double tx = hidden_bottom ? 8.0 : texels_per_m;
        s.texture = MipTexture(paint_surface(style, ext[s.u_axis], ext[s.v_axis], tx, paint_rng));
        s.texels_per_m = tx;
        s.albedo_gain = 0.85 + 0.3 * paint_rng.uniform();
        s.name = prefix + (side ? "+" : "-") + axis_names[axis];
        scene.surfaces.push_back(std::move(s));
      }
  };
  add_faces(scene.room, true, "room");
  for (size_t b = 0; b < scene.boxes.size(); ++b)
    add_faces(scene.boxes[b], false, "box" + std::to_string(b));
  return scene;
}

}  // namespace edge_slam
