#include "edge_slam/io/tum_dataset.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace edge_slam {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// Locale-independent, whole-word number parsing.
bool parse_double(const std::string& text, double& out) {
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, out);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(out);
}

[[noreturn]] void line_error(const std::string& path, int line_no, const std::string& what,
                             const std::string& line) {
  throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + what + ": '" + line + "'");
}

// Calls handle(words, line_no, line) for every non-comment, non-blank line.
template <typename Handler>
void for_each_data_line(const std::string& path, Handler handle) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path + (fs::exists(path) ? "" : " (no such file)"));
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    handle(split_words(line), line_no, line);
  }
  if (in.bad()) throw std::runtime_error("error reading " + path);
}

}  // namespace

std::vector<TumListEntry> read_tum_list(const std::string& path) {
  std::vector<TumListEntry> entries;
  for_each_data_line(path, [&](const std::vector<std::string>& w, int line_no, const std::string& line) {
    TumListEntry e;
    if (w.size() != 2 || !parse_double(w[0], e.stamp))
      line_error(path, line_no, "malformed line (expected 'timestamp filename')", line);
    e.path = w[1];
    entries.push_back(std::move(e));
  });
  std::stable_sort(entries.begin(), entries.end(),
                   [](const TumListEntry& a, const TumListEntry& b) { return a.stamp < b.stamp; });
  return entries;
}

std::vector<StampedPose> read_tum_ground_truth(const std::string& path) {
  std::vector<StampedPose> poses;
  for_each_data_line(path, [&](const std::vector<std::string>& w, int line_no, const std::string& line) {
    double v[8];
    bool ok = w.size() == 8;
    for (size_t k = 0; ok && k < 8; ++k) ok = parse_double(w[k], v[k]);
    if (!ok) line_error(path, line_no, "malformed line (expected 'timestamp tx ty tz qx qy qz qw')", line);
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (q.norm() < 1e-6) line_error(path, line_no, "zero quaternion", line);
    q.normalize();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    poses.emplace_back(v[0], T);
  });
  std::stable_sort(poses.begin(), poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.first < b.first; });
  return poses;
}

std::vector<std::pair<size_t, size_t>> associate_by_stamp(const std::vector<TumListEntry>& rgb,
                                                          const std::vector<TumListEntry>& depth,
                                                          double max_dt) {
  struct Candidate { double dt; size_t r, d; };
  std::vector<Candidate> candidates;
  // Both lists are sorted, so each colour stamp's window of depth stamps is found by a
  // moving lower bound.
  size_t lo = 0;
  for (size_t r = 0; r < rgb.size(); ++r) {
    while (lo < depth.size() && depth[lo].stamp < rgb[r].stamp - max_dt) ++lo;
    for (size_t d = lo; d < depth.size() && depth[d].stamp <= rgb[r].stamp + max_dt; ++d)
      candidates.push_back({std::abs(depth[d].stamp - rgb[r].stamp), r, d});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.dt < b.dt; });
  std::vector<bool> rgb_used(rgb.size(), false), depth_used(depth.size(), false);
  std::vector<std::pair<size_t, size_t>> pairs;
  for (const Candidate& c : candidates) {
    if (c.dt >= max_dt || rgb_used[c.r] || depth_used[c.d]) continue;  // associate.py: strict <
    rgb_used[c.r] = depth_used[c.d] = true;
    pairs.emplace_back(c.r, c.d);
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

TumDataset TumDataset::open(const std::string& folder, double max_dt) {
  if (!fs::is_directory(folder)) throw std::runtime_error("TUM dataset folder not found: " + folder);
  TumDataset ds;
  ds.folder_ = folder;
  const fs::path root(folder);
  ds.rgb_list_ = read_tum_list((root / "rgb.txt").string());
  ds.depth_list_ = read_tum_list((root / "depth.txt").string());
  const fs::path gt = root / "groundtruth.txt";
  if (fs::exists(gt)) ds.ground_truth_ = read_tum_ground_truth(gt.string());
  for (const auto& [r, d] : associate_by_stamp(ds.rgb_list_, ds.depth_list_, max_dt)) {
    TumFrame f;
    f.rgb_stamp = ds.rgb_list_[r].stamp;
    f.depth_stamp = ds.depth_list_[d].stamp;
    f.rgb_path = (root / ds.rgb_list_[r].path).string();
    f.depth_path = (root / ds.depth_list_[d].path).string();
    ds.frames_.push_back(std::move(f));
  }
  return ds;
}

cv::Mat TumDataset::load_rgb(size_t i) const {
  if (i >= frames_.size()) throw std::out_of_range("TumDataset::load_rgb: frame index out of range");
  cv::Mat img = cv::imread(frames_[i].rgb_path, cv::IMREAD_COLOR);
  if (img.empty()) throw std::runtime_error("cannot read colour image " + frames_[i].rgb_path);
  return img;
}

cv::Mat TumDataset::load_depth(size_t i) const {
  if (i >= frames_.size()) throw std::out_of_range("TumDataset::load_depth: frame index out of range");
  const std::string& path = frames_[i].depth_path;
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) throw std::runtime_error("cannot read depth image " + path);
  if (img.type() != CV_16UC1)
    throw std::runtime_error("depth image " + path + " has " + std::to_string(img.channels()) +
                             " channel(s) of " + std::to_string(img.elemSize1() * 8) +
                             " bits, expected a 16-bit single-channel PNG");
  return img;
}

cv::Mat TumDataset::load_depth_metres(size_t i, double depth_factor) const {
  cv::Mat metres;
  load_depth(i).convertTo(metres, CV_32FC1, 1.0 / depth_factor);
  return metres;
}

}  // namespace edge_slam
