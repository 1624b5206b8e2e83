// A flat JSON object of run metrics (numbers, strings, timing summaries, nested objects given
// as ready JSON), written in one go: the runner and both nodelets produce the same shape of
// metrics.json, so evaluation and benchmarks read either mode alike.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "edge_slam/util/timing_stats.h"

namespace edge_slam {

class RejectionCounter;

class MetricsJson {
 public:
  MetricsJson& number(const std::string& key, double value);
  MetricsJson& integer(const std::string& key, long long value);
  MetricsJson& text(const std::string& key, const std::string& value);
  // {"count", "mean", "median", "p95", "max"} of the values (milliseconds).
  MetricsJson& timing(const std::string& key, const std::vector<double>& values_ms);
  MetricsJson& timing_summary(const std::string& key, const TimingStats& t);  // already summarised
  MetricsJson& raw(const std::string& key, const std::string& json);  // caller-made valid JSON
  MetricsJson& object(const std::string& key, const MetricsJson& inner);

  std::string str(bool pretty = true) const;
  // Written to a temporary file and renamed, so a reader never sees half a file. Throws on error.
  void write(const std::string& path) const;

 private:
  std::vector<std::pair<std::string, std::string>> fields_;  // key, JSON value
};

// {"<kind of problem>": count, ...} of rejected inputs (util/rejection_counter.h).
MetricsJson counts_by_kind(const RejectionCounter& counter);

}  // namespace edge_slam
