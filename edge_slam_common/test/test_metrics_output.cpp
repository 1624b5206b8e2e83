// The metrics.json writer and the CSV event log both nodelets and the runner share.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "edge_slam/io/event_log.h"
#include "edge_slam/io/metrics_json.h"

namespace edge_slam {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(MetricsJson, WritesNumbersTimingsAndEscapedTextAtomically) {
  MetricsJson inner;
  inner.integer("accepted", 4);
  MetricsJson m;
  m.text("mode", "split \"mobile\"").integer("frames", 901).number("nan", std::nan("")).timing("tracking_ms", {1, 2, 3, 4})
      .object("updates", inner);
  const std::string path = ::testing::TempDir() + "/metrics_test.json";
  m.write(path);
  const std::string s = read_file(path);
  EXPECT_NE(s.find("\"mode\": \"split \\\"mobile\\\"\""), std::string::npos) << s;
  EXPECT_NE(s.find("\"frames\": 901"), std::string::npos) << s;
  EXPECT_NE(s.find("\"nan\": null"), std::string::npos) << s;
  EXPECT_NE(s.find("\"tracking_ms\": {\"count\": 4"), std::string::npos) << s;
  EXPECT_NE(s.find("\"updates\": {\"accepted\": 4}"), std::string::npos) << s;
  std::ifstream tmp(path + ".tmp");
  EXPECT_FALSE(tmp.good()) << "the temporary file is renamed away";
}

TEST(EventLog, RowsReachTheFileOnlyOnFlushAndCommasInDetailsAreReplaced) {
  const std::string path = ::testing::TempDir() + "/events_test.csv";
  {
    EventLog log(path);
    EventRow r;
    r.event = "update_applied";
    r.seq = 7;
    r.bytes = 1234;
    r.duration_ms = 12.5;
    r.detail = "accepted, rebuilt";
    log.add(r);
    EXPECT_EQ(read_file(path), std::string(EventLog::header()) + "\n");
    log.flush();
    const std::string s = read_file(path);
    EXPECT_NE(s.find(",update_applied,7,1234,-1.000,12.500,-1,accepted; rebuilt\n"), std::string::npos) << s;
  }
  EXPECT_THROW(EventLog("/nonexistent-dir/x.csv"), std::runtime_error);
  EventLog disabled;
  EXPECT_FALSE(disabled.enabled());
  disabled.add(EventRow{});  // a no-op, not a crash
}

}  // namespace
}  // namespace edge_slam
