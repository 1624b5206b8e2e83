// Unknown keys in a config file (io/config_file.h, module/slam_config.h): the known keys are
// what the loaders ask for, so a typo'd key is warned about once, naming the key it was meant
// to be, and a real key is never called unknown. The shipped config/slam.yaml has none.
#include <gtest/gtest.h>

#include <vector>

#include "edge_slam/io/config_file.h"
#include "edge_slam/module/slam_config.h"
#include "edge_slam/util/log.h"
#include "support/captured_log.h"

namespace edge_slam {
namespace {

using test_support::CapturedLog;

TEST(EditDistance, CountsInsertionsDeletionsAndSubstitutions) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("abc", ""), 3u);
  EXPECT_EQ(edit_distance("min_inliers", "min_inlier"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("update_size", "update_szie"), 2u);
}

TEST(UnknownKeys, AKeyNoLoaderAskedForIsUnknownAndAnAskedOneIsNot) {
  const ConfigMap cfg = ConfigMap::parse("tracking:\n  min_inliers: 30\n  min_inlier: 31\n", "t.yaml");
  EXPECT_EQ(cfg.unknown_keys(), (std::vector<std::string>{"tracking/min_inlier", "tracking/min_inliers"}))
      << "before any loader ran, nothing is known";
  cfg.get_int_or("tracking/min_inliers", 30);
  cfg.get_double_or("tracking/ref_ratio", 0.9);  // asked for but absent: known all the same
  EXPECT_EQ(cfg.unknown_keys(), (std::vector<std::string>{"tracking/min_inlier"}));
  EXPECT_EQ(cfg.nearest_known_key("tracking/min_inlier"), "tracking/min_inliers");
  EXPECT_EQ(cfg.nearest_known_key("camera/fx"), "") << "nothing like it: no suggestion";
}

TEST(UnknownKeys, ATypoInSlamYamlIsWarnedOnceWithTheNearestKnownKey) {
  const ConfigMap cfg =
      ConfigMap::parse("edge_slam:\n  update_szie: 8\n  update_period: 5.0\nbogus:\n  whatever: 1\n", "slam.yaml");
  CapturedLog log;
  check_slam_config(cfg);
  check_slam_config(cfg);  // a second check repeats nothing
  ASSERT_EQ(log.lines.size(), 2u);
  EXPECT_EQ(log.lines[0].first, LogLevel::kWarn);
  EXPECT_EQ(log.lines[0].second,
            "slam.yaml: unknown key 'bogus/whatever' ignored (no known key is like it)");
  EXPECT_EQ(log.lines[1].second,
            "slam.yaml: unknown key 'edge_slam/update_szie' ignored (did you mean 'edge_slam/update_size'?)");
}

TEST(UnknownKeys, TheShippedConfigHasNone) {
  const ConfigMap cfg = ConfigMap::load("../config/slam.yaml");  // tests run in edge_slam_common/
  CapturedLog log;
  check_slam_config(cfg);
  EXPECT_TRUE(cfg.unknown_keys().empty()) << cfg.unknown_keys().front();
  EXPECT_TRUE(log.lines.empty());
}

TEST(UnknownKeys, CopiesShareWhatWasAsked) {
  const ConfigMap cfg = ConfigMap::parse("orb:\n  num_features: 900\n", "o.yaml");
  const ConfigMap copy = cfg;  // NodeConfig holds the map by value
  copy.get_int_or("orb/num_features", 1000);
  EXPECT_TRUE(cfg.unknown_keys().empty());
}

}  // namespace
}  // namespace edge_slam
