#include "edge_slam/io/metrics_json.h"

#include <cmath>
#include <sstream>

#include "edge_slam/io/output_path.h"
#include "edge_slam/util/rejection_counter.h"
#include "edge_slam/util/timing_stats.h"

namespace edge_slam {
namespace {

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";  // JSON has no NaN/inf
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

}  // namespace

MetricsJson& MetricsJson::number(const std::string& key, double value) {
  fields_.emplace_back(key, json_number(value));
  return *this;
}
MetricsJson& MetricsJson::integer(const std::string& key, long long value) {
  fields_.emplace_back(key, std::to_string(value));
  return *this;
}
MetricsJson& MetricsJson::text(const std::string& key, const std::string& value) {
  fields_.emplace_back(key, quote(value));
  return *this;
}
MetricsJson& MetricsJson::timing(const std::string& key, const std::vector<double>& values_ms) {
  return timing_summary(key, summarize_times(values_ms));
}
MetricsJson& MetricsJson::timing_summary(const std::string& key, const TimingStats& t) {
  MetricsJson inner;
  inner.integer("count", static_cast<long long>(t.count))
      .number("mean", t.mean)
      .number("median", t.median)
      .number("p95", t.p95)
      .number("max", t.max);
  return object(key, inner);
}
MetricsJson& MetricsJson::raw(const std::string& key, const std::string& json) {
  fields_.emplace_back(key, json);
  return *this;
}
MetricsJson& MetricsJson::object(const std::string& key, const MetricsJson& inner) {
  fields_.emplace_back(key, inner.str(false));
  return *this;
}

std::string MetricsJson::str(bool pretty) const {
  std::string out = "{";
  for (size_t i = 0; i < fields_.size(); ++i) {
    out += (i ? "," : "");
    out += pretty ? "\n  " : (i ? " " : "");
    out += quote(fields_[i].first) + ": " + fields_[i].second;
  }
  out += pretty ? "\n}\n" : "}";
  return out;
}

void MetricsJson::write(const std::string& path) const { write_file_atomically(path, str(true)); }

MetricsJson counts_by_kind(const RejectionCounter& counter) {
  MetricsJson j;
  for (const auto& [kind, n] : counter.by_kind()) j.integer(kind, static_cast<long long>(n));
  return j;
}

}  // namespace edge_slam
