// Plain-YAML configuration reader for our own config files.
// Format: top-level "section:" lines, then indented "key: value" leaves (one level of
// nesting), "#" starts a comment. Values are kept as strings in a flat map keyed
// "section/key"; typed getters convert and range-check, and throw std::runtime_error
// naming the key, the offending value and the valid range.
// The map also records every key a getter asked for (present or not). The loaders are the only
// list of known keys: once every loader of a file ran, a key of the file none of them asked for
// is unknown (a typo, or a setting that no longer exists) and warn_unknown_keys() says so,
// naming the nearest known key. Copies of a map share that record. Not thread-safe: loaders run
// at start.
#pragma once
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace edge_slam {

class ConfigMap {
 public:
  // Parses text; `origin` (file name) is used in error messages as origin:line.
  static ConfigMap parse(const std::string& text, const std::string& origin = "<string>");
  static ConfigMap load(const std::string& path);  // throws if unreadable or malformed

  bool has(const std::string& key) const;
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
  // A value named by one of `choices` (name, value); `def` names the one taken when the key is
  // absent. Any other name throws, listing the choices.
  template <class T>
  T get_choice(const std::string& key, const std::string& def,
               std::initializer_list<std::pair<const char*, T>> choices) const {
    const std::string given = get_string(key, def);
    std::string names;
    for (const auto& [name, value] : choices) {
      if (given == name) return value;
      names += (names.empty() ? "" : ", ") + std::string(name);
    }
    throw std::runtime_error(origin_ + ": key '" + key + "' has value '" + given + "', expected one of " + names);
  }

  std::string origin() const { return origin_; }

  // Keys of the file no getter asked for (sorted), and the asked-for key nearest to `key` by
  // edit distance, or "" when none is close enough to be a likely typo of it.
  std::vector<std::string> unknown_keys() const;
  std::string nearest_known_key(const std::string& key) const;

 private:
  struct Asked {
    std::set<std::string> keys;    // every key a getter asked for
    std::set<std::string> warned;  // unknown keys already warned about
  };
  friend void warn_unknown_keys(const ConfigMap& cfg);
  const std::string& raw(const std::string& key) const;
  std::map<std::string, std::string> values_;
  std::string origin_;
  std::shared_ptr<Asked> asked_ = std::make_shared<Asked>();
};

// Logs (warning) each unknown key once: "<file>: unknown key 'a/b' ignored (did you mean 'a/c'?)".
// Call after every loader of the file ran.
void warn_unknown_keys(const ConfigMap& cfg);

// Levenshtein distance (insertions, deletions, substitutions).
size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace edge_slam
