#include "edge_slam/io/config_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "edge_slam/util/log.h"

namespace edge_slam {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Removes a trailing "# comment" that is not inside quotes.
std::string strip_comment(const std::string& s) {
  char quote = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#') {
      return s.substr(0, i);
    }
  }
  return s;
}

std::string unquote(const std::string& v) {
  if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front())
    return v.substr(1, v.size() - 2);
  return v;
}

std::string range_text(double min, double max) {
  std::ostringstream os;
  os << "[" << min << ", " << max << "]";
  return os.str();
}

}  // namespace

ConfigMap ConfigMap::parse(const std::string& text, const std::string& origin) {
  ConfigMap cfg;
  cfg.origin_ = origin;
  std::istringstream in(text);
  std::string line, section;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string body = strip_comment(line);
    const std::string t = trim(body);
    if (t.empty() || t == "---" || t.rfind("%YAML", 0) == 0) continue;
    const auto where = [&] { return origin + ":" + std::to_string(line_no) + ": "; };
    const auto colon = t.find(':');
    if (colon == std::string::npos || colon == 0)
      throw std::runtime_error(where() + "malformed line (expected 'key: value'): '" + t + "'");
    const std::string key = trim(t.substr(0, colon));
    const std::string value = trim(t.substr(colon + 1));
    if (key.find_first_of(" \t/") != std::string::npos)
      throw std::runtime_error(where() + "malformed key '" + key + "'");
    const bool indented = !body.empty() && (body[0] == ' ' || body[0] == '\t');
    if (!indented) {
      if (!value.empty()) {  // top-level leaf without a section
        cfg.values_[key] = unquote(value);
        section.clear();
      } else {
        section = key;
      }
      continue;
    }
    if (section.empty())
      throw std::runtime_error(where() + "indented key '" + key + "' outside any section");
    if (value.empty())
      throw std::runtime_error(where() + "key '" + section + "/" + key +
                               "' has no value (only one level of nesting is supported)");
    cfg.values_[section + "/" + key] = unquote(value);
  }
  return cfg;
}

ConfigMap ConfigMap::load(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot open config file '" + path + "'");
  std::stringstream ss;
  ss << f.rdbuf();
  return parse(ss.str(), path);
}

bool ConfigMap::has(const std::string& key) const {
  asked_->keys.insert(key);
  return values_.count(key) != 0;
}

const std::string& ConfigMap::raw(const std::string& key) const {
  asked_->keys.insert(key);
  const auto it = values_.find(key);
  if (it == values_.end())
    throw std::runtime_error(origin_ + ": missing required key '" + key + "'");
  return it->second;
}

std::string ConfigMap::get_string(const std::string& key) const { return raw(key); }

std::string ConfigMap::get_string(const std::string& key, const std::string& def) const {
  return has(key) ? raw(key) : def;
}

double ConfigMap::get_double(const std::string& key, double min, double max) const {
  const std::string& v = raw(key);
  size_t used = 0;
  double d = 0;
  try {
    d = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size() || !std::isfinite(d))
    throw std::runtime_error(origin_ + ": key '" + key + "' has value '" + v +
                             "', expected a number in " + range_text(min, max));
  if (d < min || d > max)
    throw std::runtime_error(origin_ + ": key '" + key + "' has value '" + v +
                             "' outside the valid range " + range_text(min, max));
  return d;
}

int ConfigMap::get_int(const std::string& key, int min, int max) const {
  const std::string& v = raw(key);
  size_t used = 0;
  long long i = 0;
  try {
    i = std::stoll(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != v.size())
    throw std::runtime_error(origin_ + ": key '" + key + "' has value '" + v +
                             "', expected an integer in " + range_text(min, max));
  if (i < min || i > max)
    throw std::runtime_error(origin_ + ": key '" + key + "' has value '" + v +
                             "' outside the valid range " + range_text(min, max));
  return static_cast<int>(i);
}

bool ConfigMap::get_bool(const std::string& key) const {
  const std::string& v = raw(key);
  if (v == "true" || v == "True" || v == "1" || v == "yes") return true;
  if (v == "false" || v == "False" || v == "0" || v == "no") return false;
  throw std::runtime_error(origin_ + ": key '" + key + "' has value '" + v +
                           "', expected true or false");
}

double ConfigMap::get_double_or(const std::string& key, double def, double min, double max) const {
  return has(key) ? get_double(key, min, max) : def;
}
int ConfigMap::get_int_or(const std::string& key, int def, int min, int max) const {
  return has(key) ? get_int(key, min, max) : def;
}
bool ConfigMap::get_bool_or(const std::string& key, bool def) const {
  return has(key) ? get_bool(key) : def;
}

std::vector<std::string> ConfigMap::unknown_keys() const {
  std::vector<std::string> unknown;
  for (const auto& [key, value] : values_)
    if (!asked_->keys.count(key)) unknown.push_back(key);
  return unknown;
}

std::string ConfigMap::nearest_known_key(const std::string& key) const {
  std::string best;
  size_t best_distance = std::string::npos;
  for (const std::string& known : asked_->keys) {
    const size_t d = edit_distance(key, known);
    if (d < best_distance) {
      best_distance = d;
      best = known;
    }
  }
  // A typo changes a few letters; beyond a third of the key it is another word altogether.
  return best_distance <= std::max<size_t>(2, key.size() / 3) ? best : "";
}

void warn_unknown_keys(const ConfigMap& cfg) {
  for (const std::string& key : cfg.unknown_keys()) {
    if (!cfg.asked_->warned.insert(key).second) continue;
    const std::string nearest = cfg.nearest_known_key(key);
    log_warn(cfg.origin() + ": unknown key '" + key + "' ignored" +
             (nearest.empty() ? " (no known key is like it)" : " (did you mean '" + nearest + "'?)"));
  }
}

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];  // row[i-1][j-1]
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace edge_slam
