// The synthetic camera and its YAML: config/camera_synthetic.yaml is exactly what
// edge_slam_synth writes as camera.yaml, so the two can never drift apart.
#include "edge_slam/sim/synthetic_camera.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace edge_slam;

TEST(SynthCamera, IntrinsicsAreTheDocumentedOnes) {
  const PinholeCamera c = synthetic_room_camera();
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.height, 480);
  EXPECT_EQ(c.fx, 525.0);
  EXPECT_EQ(c.fy, 525.0);
  EXPECT_EQ(c.cx, 319.5);
  EXPECT_EQ(c.cy, 239.5);
  EXPECT_FALSE(c.has_distortion());
  EXPECT_EQ(c.depth_factor, 5000.0);
  EXPECT_NEAR(c.th_depth, 4.0 * 400.0 / 525.0, 1e-12);  // metres in the struct: 3.05 m, as with bf 40
  EXPECT_EQ(c.fps, 30.0);
}

TEST(SynthCamera, ConfigFileMatchesGeneratedCameraYaml) {
  std::ifstream in("../config/camera_synthetic.yaml");  // tests run in edge_slam_common/
  ASSERT_TRUE(in) << "config/camera_synthetic.yaml missing";
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), camera_yaml(synthetic_room_camera(),
                                    "Synthetic room camera (rendered by edge_slam_synth): exact pinhole, no distortion."));
}

TEST(SynthCamera, YamlHasEveryKeyOnce) {
  const std::string y = camera_yaml(synthetic_room_camera(15.0), "t");
  for (const char* key : {"name", "width", "height", "fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3",
                          "fps", "rolling_shutter_readout", "bf", "th_depth", "depth_factor", "rgb_encoding"}) {
    const std::string needle = std::string("\n  ") + key + ": ";
    const size_t at = y.find(needle);
    ASSERT_NE(at, std::string::npos) << key;
    EXPECT_EQ(y.find(needle, at + 1), std::string::npos) << key;
  }
  EXPECT_NE(y.find("  fps: 15.0 "), std::string::npos);
  EXPECT_NE(y.find("  th_depth: 4.0 "), std::string::npos);  // baselines: 3.05 m with bf 400
}
