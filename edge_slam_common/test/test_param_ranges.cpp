// Out-of-range split-system parameters are refused when loaded, and the error names the key,
// the value and the valid range, so a nodelet refuses to start with a message saying what to fix.
#include <gtest/gtest.h>

#include <string>

#include "edge_slam/io/config_file.h"
#include "edge_slam/module/edge_session.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/module/tracking_params.h"

using namespace edge_slam;

namespace {

// The error text of loading `key: value` into `load`, or "" when it loaded.
template <typename Load>
std::string refusal(const std::string& key, const std::string& value, Load load) {
  const size_t slash = key.find('/');
  const std::string text = key.substr(0, slash) + ":\n  " + key.substr(slash + 1) + ": " + value + "\n";
  try {
    load(ConfigMap::parse(text, "slam.yaml"));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

void expect_refused(const std::string& error, const std::string& key, const std::string& range) {
  EXPECT_NE(error.find(key), std::string::npos) << error;
  EXPECT_NE(error.find(range), std::string::npos) << error;
}

}  // namespace

TEST(ParamRanges, EdgeRefusesBadUpdatePeriodAndSizes) {
  auto edge = [](const ConfigMap& c) { load_edge_session_params(c); };
  expect_refused(refusal("edge_slam/update_period", "-1", edge), "edge_slam/update_period", "[0.05");
  expect_refused(refusal("edge_slam/update_period", "nan", edge), "edge_slam/update_period", "0.05");
  expect_refused(refusal("edge_slam/update_size", "0", edge), "edge_slam/update_size", "[1");
  expect_refused(refusal("edge_slam/local_map_cap", "0", edge), "edge_slam/local_map_cap", "[6");
  EXPECT_EQ(refusal("edge_slam/update_period", "2.5", edge), "");
}

TEST(ParamRanges, MobileRefusesBadTimeConstraintAndCap) {
  auto mobile = [](const ConfigMap& c) { load_mobile_session_params(c); };
  expect_refused(refusal("edge_slam/initial_time_constraint", "-0.1", mobile), "edge_slam/initial_time_constraint",
                 "[0");
  expect_refused(refusal("edge_slam/local_map_cap", "0", mobile), "edge_slam/local_map_cap", "[6");
  expect_refused(refusal("edge_slam/relocalization_frame_period", "-2", mobile),
                 "edge_slam/relocalization_frame_period", "[0");
  EXPECT_EQ(refusal("edge_slam/local_map_cap", "40", mobile), "");
}

TEST(ParamRanges, OrbRefusesNoFeatures) {
  auto orb = [](const ConfigMap& c) { load_orb_params(c); };
  expect_refused(refusal("orb/num_features", "0", orb), "orb/num_features", "[50");
  expect_refused(refusal("orb/num_features", "-5", orb), "orb/num_features", "[50");
  expect_refused(refusal("orb/num_levels", "0", orb), "orb/num_levels", "[1");
}
