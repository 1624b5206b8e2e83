// Plain-YAML configuration reader for our own config files.
// Format: top-level "section:" lines, then indented "key: value" leaves (one level of
// nesting), "#" starts a comment. Values are kept as strings in a flat map keyed
// "section/key"; typed getters convert and range-check, and throw std::runtime_error
// naming the key, the offending value and the valid range.
#pragma once
#include <limits>
#include <map>
#include <string>

namespace edge_slam {

class ConfigMap {
 public:
  // Parses text; `origin` (file name) is used in error messages as origin:line.
  static ConfigMap parse(const std::string& text, const std::string& origin = "<string>");
  static ConfigMap load(const std::string& path);  // throws if unreadable or malformed

  bool has(const std::string& key) const { return values_.count(key) != 0; }
  const std::map<std::string, std::string>& values() const { return values_; }
  void set(const std::string& key, const std::string& value) { values_[key] = value; }

  // Required getters throw when the key is missing.
  std::string get_string(const std::string& key) const;
  double get_double(const std::string& key, double min = -std::numeric_limits<double>::max(),
                    double max = std::numeric_limits<double>::max()) const;
  int get_int(const std::string& key, int min = std::numeric_limits<int>::min(),
              int max = std::numeric_limits<int>::max()) const;
  bool get_bool(const std::string& key) const;

  // Optional getters return the default when the key is missing, but still throw
  // when a present value is malformed or out of range.
  std::string get_string(const std::string& key, const std::string& def) const;
  double get_double_or(const std::string& key, double def,
                       double min = -std::numeric_limits<double>::max(),
                       double max = std::numeric_limits<double>::max()) const;
  int get_int_or(const std::string& key, int def, int min = std::numeric_limits<int>::min(),
                 int max = std::numeric_limits<int>::max()) const;
  bool get_bool_or(const std::string& key, bool def) const;

  std::string origin() const { return origin_; }

 private:
  const std::string& raw(const std::string& key) const;
  std::map<std::string, std::string> values_;
  std::string origin_;
};

}  // namespace edge_slam
