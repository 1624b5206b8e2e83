// The metrics.json writer and the CSV event log both nodelets and the runner share. The JSON
// is parsed (nlohmann-json) and the CSV split into fields by its header, never matched as text.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

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

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, sep)) out.push_back(field);
  if (!line.empty() && line.back() == sep) out.push_back("");
  return out;
}

// The data rows of an EventLog file, each as column name -> value (by the file's own header).
std::vector<std::map<std::string, std::string>> csv_rows(const std::string& text) {
  std::stringstream in(text);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split(line, ',');
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line, ',');
    EXPECT_EQ(fields.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
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
  const std::string s = read_file(path);
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
    r.detail = "accepted, rebuilt";
    log.add(r);
    EXPECT_EQ(read_file(path), std::string(EventLog::header()) + "\n");
    log.flush();
    const std::string s = read_file(path);
    const auto rows = csv_rows(s);
    ASSERT_EQ(rows.size(), 1u) << s;
    const auto& row = rows[0];
    EXPECT_EQ(row.at("event"), "update_applied");
    EXPECT_EQ(row.at("seq"), "7");
    EXPECT_EQ(row.at("bytes"), "1234");
    EXPECT_DOUBLE_EQ(std::stod(row.at("latency_ms")), -1.0) << "not applicable";
    EXPECT_DOUBLE_EQ(std::stod(row.at("duration_ms")), 12.5);
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

}  // namespace
}  // namespace edge_slam
