#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "edge_slam/camera/camera_loader.h"
#include "edge_slam/io/config_file.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/loop_verifier.h"
#include "edge_slam/module/local_mapping_params.h"
#include "edge_slam/module/tracking_params.h"

using namespace edge_slam;

namespace {
const char* kCamera =
    "# comment line\n"
    "camera:\n"
    "  name: test   # trailing comment\n"
    "  width: 640\n"
    "  height: 480\n"
    "  fx: 500.0\n"
    "  fy: 500.0\n"
    "  cx: 319.5\n"
    "  cy: 239.5\n"
    "  bf: 40.0\n"
    "  th_depth: 40.0\n"
    "  depth_factor: 5000\n"
    "  rgb_encoding: \"rgb8\"\n";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Config, ParsesSectionsIntoFlatKeys) {
  const ConfigMap cfg = ConfigMap::parse(kCamera, "cam.yaml");
  EXPECT_EQ(cfg.get_string("camera/name"), "test");
  EXPECT_EQ(cfg.get_int("camera/width"), 640);
  EXPECT_DOUBLE_EQ(cfg.get_double("camera/cx"), 319.5);
  EXPECT_EQ(cfg.get_string("camera/rgb_encoding"), "rgb8");
  EXPECT_FALSE(cfg.has("name"));
}

TEST(Config, MissingKeyNamesTheKey) {
  const ConfigMap cfg = ConfigMap::parse(kCamera, "cam.yaml");
  const std::string e = error_of([&] { cfg.get_double("camera/k9"); });
  EXPECT_NE(e.find("camera/k9"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
  EXPECT_DOUBLE_EQ(cfg.get_double_or("camera/k9", 1.5), 1.5);
}

TEST(Config, OutOfRangeNamesKeyValueAndRange) {
  const ConfigMap cfg = ConfigMap::parse("tracking:\n  ref_ratio: 1.5\n  n: 12x\n", "s.yaml");
  const std::string e = error_of([&] { cfg.get_double("tracking/ref_ratio", 0.0, 1.0); });
  EXPECT_NE(e.find("tracking/ref_ratio"), std::string::npos) << e;
  EXPECT_NE(e.find("1.5"), std::string::npos) << e;
  EXPECT_NE(e.find("[0, 1]"), std::string::npos) << e;
  const std::string e2 = error_of([&] { cfg.get_int("tracking/n"); });
  EXPECT_NE(e2.find("12x"), std::string::npos) << e2;
  EXPECT_THROW(load_tracking_params(cfg), std::runtime_error);
}

TEST(Config, ChoiceTakesANamedValueTheDefaultOrNamesTheChoices) {
  const ConfigMap cfg = ConfigMap::parse("tracking:\n  mode: fast\n  other: slowest\n", "s.yaml");
  const auto choose = [&](const std::string& key) {
    return cfg.get_choice<int>(key, "slow", {{"slow", 1}, {"fast", 2}});
  };
  EXPECT_EQ(choose("tracking/mode"), 2);
  EXPECT_EQ(choose("tracking/absent"), 1);
  const std::string e = error_of([&] { choose("tracking/other"); });
  EXPECT_NE(e.find("s.yaml: key 'tracking/other' has value 'slowest', expected one of slow, fast"), std::string::npos)
      << e;
}

TEST(Config, MalformedLinesReportFileAndLine) {
  std::string e = error_of([] { ConfigMap::parse("camera:\n  fx 500\n", "bad.yaml"); });
  EXPECT_NE(e.find("bad.yaml:2"), std::string::npos) << e;
  e = error_of([] { ConfigMap::parse("  fx: 500\n", "bad.yaml"); });
  EXPECT_NE(e.find("bad.yaml:1"), std::string::npos) << e;
  e = error_of([] { ConfigMap::parse("camera:\n  sub:\n", "bad.yaml"); });
  EXPECT_NE(e.find("bad.yaml:2"), std::string::npos) << e;
  EXPECT_THROW(ConfigMap::load("/nonexistent/file.yaml"), std::runtime_error);
}

TEST(Config, CameraThDepthIsConvertedFromBaselines) {
  const PinholeCamera cam = load_camera(ConfigMap::parse(kCamera));
  EXPECT_EQ(cam.width, 640);
  EXPECT_NEAR(cam.th_depth, 40.0 * 40.0 / 500.0, 1e-12);
  EXPECT_NEAR(cam.baseline(), 0.08, 1e-12);
  EXPECT_DOUBLE_EQ(cam.depth_factor, 5000);
  EXPECT_FALSE(cam.has_distortion());
  EXPECT_EQ(load_rgb_encoding(ConfigMap::parse(kCamera)), RgbEncoding::kRgb);
}

TEST(Config, CameraRejectsBadValues) {
  ConfigMap cfg = ConfigMap::parse(kCamera);
  cfg.set("camera/fx", "-3");
  EXPECT_NE(error_of([&] { load_camera(cfg); }).find("camera/fx"), std::string::npos);
  cfg = ConfigMap::parse(kCamera);
  cfg.set("camera/rgb_encoding", "yuv");
  EXPECT_NE(error_of([&] { load_camera(cfg); }).find("rgb_encoding"), std::string::npos);
}

TEST(Config, ShippedConfigsLoad) {
  // Tests run from edge_slam_common/.
  const PinholeCamera cam = load_camera("../config/camera_tum1.yaml");
  EXPECT_NEAR(cam.fx, 517.306408, 1e-9);
  EXPECT_TRUE(cam.has_distortion());
  EXPECT_NEAR(cam.th_depth, 40.0 * 40.0 / 517.306408, 1e-9);
  const ConfigMap slam = ConfigMap::load("../config/slam.yaml");
  const OrbParams orb = load_orb_params(slam);
  EXPECT_EQ(orb.num_features, 1000);
  EXPECT_EQ(orb.num_levels, 8);
  const TrackingParams tp = load_tracking_params(slam);
  EXPECT_EQ(tp.keyframe.max_frames_between_keyframes, 20);
  EXPECT_DOUBLE_EQ(tp.keyframe.ref_ratio, 0.9);
  EXPECT_DOUBLE_EQ(slam.get_double("edge_slam/initial_time_constraint"), 0.3);
  EXPECT_EQ(slam.get_int("edge_slam/update_size"), 6);
  EXPECT_EQ(tp.conditions, KeyFrameConditionSet::kAll);
  ConfigMap mobile = slam;
  mobile.set("tracking/keyframe_conditions", "mobile");
  EXPECT_EQ(load_tracking_params(mobile).conditions, KeyFrameConditionSet::kMobile);
  mobile.set("tracking/keyframe_conditions", "sometimes");
  EXPECT_NE(error_of([&] { load_tracking_params(mobile); }).find("keyframe_conditions"), std::string::npos);
  // The edge's re-anchoring of late KeyFrames is on as shipped; false restores the paper's insertion as received.
  EXPECT_TRUE(load_edge_session_params(slam).reanchor_late_keyframes);
  ConfigMap paper = slam;
  paper.set("edge_slam/reanchor_late_keyframes", "false");
  EXPECT_FALSE(load_edge_session_params(paper).reanchor_late_keyframes);
  // The early update on divergence (module/update_trigger.h): shipped at 2 cm; 0 = the paper's timer only.
  const UpdateTriggerParams trigger = load_edge_session_params(slam).update_trigger;
  EXPECT_DOUBLE_EQ(trigger.divergence_m, 0.02);
  EXPECT_DOUBLE_EQ(trigger.min_gap_s, 1.0);
  ConfigMap early = slam;
  early.set("edge_slam/update_on_divergence", "0");
  EXPECT_DOUBLE_EQ(load_edge_session_params(early).update_trigger.divergence_m, 0.0);
  early.set("edge_slam/update_on_divergence", "-0.5");
  EXPECT_NE(error_of([&] { load_edge_session_params(early); }).find("update_on_divergence"), std::string::npos);
}

TEST(Config, LoopVerificationLoadsForTheEdgeAndTheRunner) {
  const ConfigMap slam = ConfigMap::load("../config/slam.yaml");
  ASSERT_TRUE(slam.has("loop_closing/verify_with_depth"));  // documented in the shipped file
  ASSERT_TRUE(slam.has("loop_closing/refine_on_loop_group"));
  const LoopVerifierParams v = load_loop_verifier_params(slam);
  EXPECT_TRUE(v.refine_with_depth);
  EXPECT_TRUE(v.refine_on_loop_group);
  // The edge hosts loop closing: the same keys reach its loop verifier.
  ConfigMap orb = slam;
  orb.set("loop_closing/verify_with_depth", "false");
  orb.set("loop_closing/refine_on_loop_group", "false");
  const EdgeSessionParams edge = load_edge_session_params(orb);
  EXPECT_FALSE(edge.loop.verifier.refine_with_depth);
  EXPECT_FALSE(edge.loop.verifier.refine_on_loop_group);
  orb.set("loop_closing/verify_with_depth", "sometimes");
  EXPECT_NE(error_of([&] { load_loop_verifier_params(orb); }).find("verify_with_depth"), std::string::npos);
}

TEST(Config, LocalMappingSectionLoadsAndRejectsBadValues) {
  const ConfigMap slam = ConfigMap::load("../config/slam.yaml");
  ASSERT_TRUE(slam.has("local_mapping/ba_first_pass_iterations"));  // documented in the shipped file
  const LocalMappingParams lm = load_local_mapping_params(slam);
  EXPECT_EQ(lm.ba_first_pass_iterations, 5);
  EXPECT_EQ(lm.ba_second_pass_iterations, 10);
  EXPECT_EQ(lm.triangulation.num_covisibles, 10u);
  EXPECT_FLOAT_EQ(lm.point_culling.min_found_ratio, 0.25f);
  EXPECT_DOUBLE_EQ(lm.keyframe_culling.redundant_ratio, 0.9);
  EXPECT_TRUE(lm.local_ba);
  EXPECT_EQ(lm.ba_window.max_free_keyframes, 0u);  // ORB-SLAM2's unbounded window unless configured
  EXPECT_EQ(lm.ba_window.max_fixed_keyframes, 0u);
  ConfigMap tuned = slam;
  tuned.set("local_mapping/ba_max_free_keyframes", "20");
  tuned.set("local_mapping/ba_max_fixed_keyframes", "15");
  EXPECT_EQ(load_local_mapping_params(tuned).ba_window.max_free_keyframes, 20u);
  EXPECT_EQ(load_local_mapping_params(tuned).ba_window.max_fixed_keyframes, 15u);
  // The edge hosts Local-Mapping: it reads the same section (it used to keep the defaults).
  EXPECT_EQ(load_edge_session_params(tuned).mapping.ba_window.max_free_keyframes, 20u);
  tuned.set("local_mapping/triangulation_covisibles", "7");
  EXPECT_EQ(load_edge_session_params(tuned).mapping.triangulation.num_covisibles, 7u);
  ConfigMap bad = slam;
  bad.set("local_mapping/ba_first_pass_iterations", "0");
  EXPECT_NE(error_of([&] { load_local_mapping_params(bad); }).find("ba_first_pass_iterations"), std::string::npos);
  bad = slam;
  bad.set("local_mapping/keyframe_redundant_ratio", "1.5");
  EXPECT_NE(error_of([&] { load_local_mapping_params(bad); }).find("keyframe_redundant_ratio"), std::string::npos);
  const LocalMappingParams defaults = load_local_mapping_params(ConfigMap::parse("orb:\n  num_levels: 8\n"));
  EXPECT_EQ(defaults.ba_second_pass_iterations, 10);
}

