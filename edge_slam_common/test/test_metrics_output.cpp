// The metrics.json writer and the CSV event log both nodelets and the runner share. The JSON
// is parsed (nlohmann-json) and the CSV split into fields by its header, never matched as text:
// the typed columns the Python reads (kind, decision, deferred, frame_stamp ...) by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "edge_slam/io/event_log.h"
#include "edge_slam/io/metrics_json.h"
#include "support/csv_rows.h"

namespace edge_slam {
namespace {

using test_support::file_text;

// The data rows of an EventLog file, each as column name -> value (by the file's own header).
std::vector<std::map<std::string, std::string>> csv_rows(const std::string& path) {
  size_t malformed = 0;
  auto rows = test_support::read_csv_rows(path, &malformed);
  EXPECT_EQ(malformed, 0u) << "a row with more or fewer fields than the header";
  return rows;
}

TEST(MetricsJson, WritesNumbersTimingsAndEscapedTextAtomically) {
  MetricsJson inner;
  inner.integer("accepted", 4);
  MetricsJson m;
  m.text("mode", "split \"mobile\"").integer("frames", 901).number("nan", std::nan("")).timing("tracking_ms", {1, 2, 3, 4})
      .object("updates", inner);
  const std::string path = ::testing::TempDir() + "/metrics_test.json";
  m.write(path);
  const std::string s = file_text(path);
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(s)) << s;
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.at("mode"), "split \"mobile\"");
  EXPECT_EQ(j.at("frames"), 901);
  EXPECT_TRUE(j.at("frames").is_number_integer());
  EXPECT_TRUE(j.at("nan").is_null()) << "NaN is not JSON: written as null";
  const nlohmann::json& t = j.at("tracking_ms");
  EXPECT_EQ(t.at("count"), 4);
  EXPECT_DOUBLE_EQ(t.at("mean").get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(t.at("median").get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(t.at("max").get<double>(), 4.0);
  EXPECT_EQ(j.at("updates"), nlohmann::json({{"accepted", 4}}));
  EXPECT_EQ(j.size(), 5u) << s;
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
    r.cpu_ms = 9.25;
    r.inliers = 212;
    r.detail = "accepted, rebuilt";
    log.add(r);
    EXPECT_EQ(file_text(path), std::string(EventLog::header()) + "\n");
    log.flush();
    const std::string s = file_text(path);
    const auto rows = csv_rows(path);
    ASSERT_EQ(rows.size(), 1u) << s;
    const auto& row = rows[0];
    EXPECT_EQ(row.at("event"), "update_applied");
    EXPECT_EQ(row.at("seq"), "7");
    EXPECT_EQ(row.at("bytes"), "1234");
    EXPECT_DOUBLE_EQ(std::stod(row.at("latency_ms")), -1.0) << "not applicable";
    EXPECT_DOUBLE_EQ(std::stod(row.at("duration_ms")), 12.5);
    EXPECT_DOUBLE_EQ(std::stod(row.at("cpu_ms")), 9.25);
    EXPECT_EQ(row.at("inliers"), "212");
    EXPECT_EQ(row.at("map_keyframes"), "-1");
    EXPECT_EQ(row.at("detail"), "accepted; rebuilt") << "a comma in the detail would add a column";
  }
  EXPECT_THROW(EventLog("/proc/no-such-folder/x.csv"), std::runtime_error);
  const std::string nested = ::testing::TempDir() + "/events_test_dir/a/b.csv";
  EXPECT_TRUE(EventLog(nested).enabled()) << "missing folders are created";
  EventLog disabled;
  EXPECT_FALSE(disabled.enabled());
  disabled.add(EventRow{});  // a no-op, not a crash
}

TEST(EventLog, RowsReadBackByColumnNameWithTheTypedColumns) {
  const std::string path = ::testing::TempDir() + "/events_typed.csv";
  {
    EventLog log(path, [] { return 1700000000.25; });
    EventRow update;
    update.event = "update";
    update.data_time = 12.5;
    update.seq = 4;
    update.bytes = 0;
    update.duration_ms = 16.0;
    update.map_keyframes = 6;
    update.frame_stamp = 12.466667;
    update.kind = "periodic";
    update.decision = "accepted";
    update.deferred = 1;
    log.add(update);
    EventRow verdict;
    verdict.event = "keyframe";
    verdict.decision = "condition 2 (busy, too soon)";  // a comma would break the CSV
    log.add(verdict);
  }
  const auto rows = csv_rows(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("wall_time"), "1700000000.250000") << "stamped by the injected clock";
  EXPECT_EQ(rows[0].at("event"), "update");
  EXPECT_EQ(rows[0].at("kind"), "periodic");
  EXPECT_EQ(rows[0].at("decision"), "accepted");
  EXPECT_EQ(rows[0].at("deferred"), "1");
  EXPECT_DOUBLE_EQ(std::stod(rows[0].at("frame_stamp")), 12.466667);
  EXPECT_DOUBLE_EQ(std::stod(rows[0].at("duration_ms")), 16.0);
  EXPECT_EQ(rows[0].at("detail"), "");
  EXPECT_EQ(rows[1].at("decision"), "condition 2 (busy; too soon)");
  EXPECT_EQ(rows[1].at("deferred"), "0");
  EXPECT_EQ(rows[1].at("frame_stamp"), "-1.000000") << "does not apply";
  std::remove(path.c_str());
}

}  // namespace
}  // namespace edge_slam
