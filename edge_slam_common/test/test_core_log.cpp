// The core's log (util/log.h): a settable sink that gets every line with its level, stderr by
// default (the tools), and the rejection reports built on it (util/rejection_log.h): the first
// of each kind of problem at once, then at most one line per throttle period, time an argument.
#include <gtest/gtest.h>

#include <vector>

#include "edge_slam/util/log.h"
#include "support/captured_log.h"
#include "edge_slam/util/rejection_log.h"

namespace edge_slam {
namespace {

using test_support::CapturedLog;

TEST(CoreLog, TheSinkGetsEachLineWithItsLevel) {
  CapturedLog log;
  log_warn("[loop] queue full: oldest keyframe dropped");
  log_error(log_text("KeyFrame ", 12, " refused: ", 3.5, "\n"));
  ASSERT_EQ(log.lines.size(), 2u);
  EXPECT_EQ(log.lines[0].first, LogLevel::kWarn);
  EXPECT_EQ(log.lines[1].first, LogLevel::kError);
  EXPECT_EQ(log.lines[1].second, "KeyFrame 12 refused: 3.5") << "one line: the trailing newline goes";
}

TEST(CoreLog, WithoutASinkLinesGoToStderrAndDebugOnlyWhenAsked) {
  const LogSink previous = set_log_sink(nullptr);
  testing::internal::CaptureStderr();
  log_info("[slam] hello");
  log_debug("not shown");
  set_stderr_log_level(LogLevel::kDebug);
  log_debug("shown");
  set_stderr_log_level(LogLevel::kInfo);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "[slam] hello\nshown\n");
  set_log_sink(previous);
}

TEST(RejectionLog, FirstOfEachKindAtOnceThenThrottledWithTotals) {
  CapturedLog log;
  RejectionLog r("rejecting a malformed map update", "rejecting malformed map updates", 5.0);
  EXPECT_EQ(r.reject("keypoint index 7 >= 5", 100.0), 1u);
  EXPECT_EQ(r.reject("keypoint index 9 >= 5", 100.1), 2u) << "the same kind: digits do not matter";
  EXPECT_EQ(r.reject("keypoint index 9 >= 5", 101.0), 3u);
  EXPECT_EQ(r.reject("descriptors hold 33 bytes", 101.5), 1u) << "a new kind";
  EXPECT_EQ(r.reject("keypoint index 1 >= 5", 106.0), 4u);
  EXPECT_EQ(r.total(), 5u);
  ASSERT_EQ(log.lines.size(), 4u);
  EXPECT_EQ(log.lines[0].second, "rejecting a malformed map update (first of its kind): keypoint index 7 >= 5");
  EXPECT_EQ(log.lines[1].second, "rejecting malformed map updates (2 so far, 2 like this): keypoint index 9 >= 5")
      << "the first repeat is reported; the next ones within 5 s are not";
  EXPECT_EQ(log.lines[2].second, "rejecting a malformed map update (first of its kind): descriptors hold 33 bytes")
      << "a new kind is never throttled";
  EXPECT_EQ(log.lines[3].second, "rejecting malformed map updates (5 so far, 4 like this): keypoint index 1 >= 5");
  for (const auto& line : log.lines) EXPECT_EQ(line.first, LogLevel::kError);
}

}  // namespace
}  // namespace edge_slam
