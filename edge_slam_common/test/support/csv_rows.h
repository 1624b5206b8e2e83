// Test helper: a CSV with a header line as rows of column name -> text (the event CSV is read
// by name, as the Python does, never by position).
#pragma once
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace edge_slam {
namespace test_support {

inline std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  for (std::string field; std::getline(s, field, ',');) out.push_back(field);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// Every row must have as many fields as the header: a stray comma would shift the columns.
inline std::vector<std::map<std::string, std::string>> read_csv_rows(const std::string& path,
                                                                     size_t* malformed = nullptr) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_fields(line);
  std::vector<std::map<std::string, std::string>> rows;
  if (malformed) *malformed = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = csv_fields(line);
    if (malformed && fields.size() != header.size()) ++*malformed;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

inline std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace test_support
}  // namespace edge_slam
