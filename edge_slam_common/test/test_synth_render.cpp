// Rendering of the synthetic room: byte-identical output for a seed, depth that matches the
// exact geometry, and enough stable texture for ORB/FAST.
#include "edge_slam/sim/ray_cast.h"
#include "edge_slam/sim/renderer.h"
#include "edge_slam/sim/scene.h"
#include "edge_slam/sim/synthetic_camera.h"
#include "edge_slam/sim/trajectory.h"

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <memory>
#include <vector>

using namespace edge_slam;

namespace {

std::vector<uchar> encode_png(const cv::Mat& img) {
  std::vector<uchar> bytes;
  EXPECT_TRUE(cv::imencode(".png", img, bytes));
  return bytes;
}

// A camera at `position` looking horizontally along world direction `forward` (unit, in xy).
Eigen::Isometry3d looking(const Eigen::Vector3d& position, const Eigen::Vector3d& forward) {
  const Eigen::Vector3d down(0, 0, -1);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = down.cross(forward);  // x right = y_down x z_forward
  T.linear().col(1) = down;
  T.linear().col(2) = forward;
  T.translation() = position;
  return T;
}

const std::vector<double> kSampleTimes = {0.0, 7.5, 15.3, 22.5};

class SynthRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { scene_ = std::make_unique<Scene>(Scene::build(42)); }
  static void TearDownTestSuite() { scene_.reset(); }
  static std::unique_ptr<Scene> scene_;
};
std::unique_ptr<Scene> SynthRender::scene_;

}  // namespace

TEST_F(SynthRender, SameSeedGivesByteIdenticalFramesOtherSeedDiffers) {
  const PinholeCamera cam = synthetic_room_camera();
  const Trajectory traj(42);
  // Independently built scenes (at a lower texture resolution, to keep the test fast).
  const Scene first = Scene::build(42, 64), again = Scene::build(42, 64), other = Scene::build(43, 64);
  for (double t : {0.0, 15.3}) {
    RenderedFrame a = render(first, cam, traj.pose_at(t));
    RenderedFrame b = render(again, cam, traj.pose_at(t));
    add_sensor_noise(a.bgr, 42, 7);
    add_sensor_noise(b.bgr, 42, 7);
    EXPECT_EQ(encode_png(a.bgr), encode_png(b.bgr)) << "t=" << t;
    EXPECT_EQ(encode_png(depth_to_tum16(a.depth)), encode_png(depth_to_tum16(b.depth)));
    RenderedFrame c = render(other, cam, traj.pose_at(t));
    add_sensor_noise(c.bgr, 42, 7);
    EXPECT_NE(encode_png(a.bgr), encode_png(c.bgr));
  }
  // Different seeds also move the camera differently (hand-held wobble).
  EXPECT_GT((Trajectory(42).pose_at(3).translation() - Trajectory(43).pose_at(3).translation()).norm(), 1e-4);
}

TEST_F(SynthRender, EnoughCornersEverywhereForOrb) {
  const PinholeCamera cam = synthetic_room_camera();
  const Trajectory traj(42);
  for (double t : kSampleTimes) {
    const RenderedFrame f = render(*scene_, cam, traj.pose_at(t));
    cv::Mat grey;
    cv::cvtColor(f.bgr, grey, cv::COLOR_BGR2GRAY);
    std::vector<cv::KeyPoint> corners;
    cv::FAST(grey, corners, 20, true);
    EXPECT_GT(corners.size(), 1000u) << "t=" << t;
    // Spread over the image, not only in one textured corner: every quadrant has corners.
    int quadrant_counts[4] = {};
    for (const cv::KeyPoint& k : corners)
      ++quadrant_counts[(k.pt.x > cam.width / 2 ? 1 : 0) + (k.pt.y > cam.height / 2 ? 2 : 0)];
    for (int q = 0; q < 4; ++q) EXPECT_GT(quadrant_counts[q], 100) << "t=" << t << " quadrant " << q;
  }
}

TEST(SynthGeometry, WallStraightAheadReadsItsExactDistance) {
  const Scene scene = Scene::build(42, 16);  // coarse textures: only geometry is tested
  const PinholeCamera cam = synthetic_room_camera();
  // 2.5 m up, 3 m from the -y wall, facing it: above all furniture.
  const RenderedFrame f = render(scene, cam, looking({-1.0, 0.0, 2.5}, {0, -1, 0}));
  int checked = 0;
  for (int v = 175; v < 330; v += 5)
    for (int u = 200; u < 440; u += 5) {
      EXPECT_FLOAT_EQ(f.depth.at<float>(v, u), 3.0f) << u << "," << v;
      ++checked;
    }
  EXPECT_GT(checked, 1000);  // rows 175..330 stay below the ceiling, columns clear of furniture
  EXPECT_EQ(depth_to_tum16(f.depth).at<uint16_t>(240, 320), 15000);
  // Beyond max_depth there is no reading.
  RenderOptions near_only;
  near_only.max_depth = 2.0;
  EXPECT_EQ(render(scene, cam, looking({-1.0, 0.0, 2.5}, {0, -1, 0}), near_only).depth.at<float>(240, 320), 0.0f);
  // The ray query agrees: 3 m along -y, 1.5 m along +y (the cabinet's top is below 2.5 m).
  EXPECT_DOUBLE_EQ(hit_depth(scene, {-1.0, 0.0, 2.5}, {0, -1, 0}), 3.0);
  EXPECT_DOUBLE_EQ(hit_depth(scene, {0.0, 0.0, 1.0}, {0, 0, 1}), 2.0);  // ceiling
}

TEST(SynthGeometry, EveryDepthPixelUnprojectsOntoASurface) {
  const Scene scene = Scene::build(42, 16);
  const PinholeCamera cam = synthetic_room_camera();
  const Trajectory traj(42);
  for (double t : kSampleTimes) {
    const Eigen::Isometry3d T_wc = traj.pose_at(t);
    RenderOptions fast;
    fast.supersample = 1;
    const RenderedFrame f = render(scene, cam, T_wc, fast);
    const cv::Mat raw = depth_to_tum16(f.depth);
    int valid = 0;
    for (int v = 0; v < cam.height; v += 7)
      for (int u = 0; u < cam.width; u += 7) {
        const float z = f.depth.at<float>(v, u);
        if (z <= 0) continue;
        ++valid;
        // Exactly the ray-cast depth of the pixel-centre ray...
        const Eigen::Vector3d dir = T_wc.linear() * Eigen::Vector3d((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1);
        EXPECT_NEAR(z, hit_depth(scene, T_wc.translation(), dir), 1e-5);
        // ...and the stored 16-bit depth lands on a surface within 1 mm.
        const Eigen::Vector3d p = T_wc * cam.unproject(u, v, raw.at<uint16_t>(v, u) / cam.depth_factor);
        EXPECT_TRUE(on_surface(scene, p, 1e-3)) << "t=" << t << " pixel " << u << "," << v;
      }
    EXPECT_GT(valid, 5000) << "t=" << t;
  }
}
