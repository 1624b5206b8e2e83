// Micro-benchmark: our OrbExtractor against cv::ORB (1000 features, scale 1.2, 8 levels),
// interleaved frame by frame in one run so both see the same machine load.
// Usage: orb_benchmark <TUM sequence folder | image folder> [--frames N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numeric>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "edge_slam/feature/orb_extractor.h"

namespace fs = std::filesystem;

namespace {

// TUM folder: the images listed in rgb.txt; otherwise every .png/.jpg in the folder, sorted.
std::vector<fs::path> list_images(const fs::path& folder) {
  std::vector<fs::path> images;
  std::ifstream rgb_list(folder / "rgb.txt");
  if (rgb_list) {
    std::string line;
    while (std::getline(rgb_list, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string stamp, file;
      if (fields >> stamp >> file) images.push_back(folder / file);
    }
    return images;
  }
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") images.push_back(entry.path());
  }
  std::sort(images.begin(), images.end());
  return images;
}

struct Stats {
  std::vector<double> ms;
  std::vector<size_t> counts;
  void print(const char* name) const {
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size();
    const double median = sorted[sorted.size() / 2];
    const double kps = std::accumulate(counts.begin(), counts.end(), 0.0) / counts.size();
    std::printf("%-10s mean %7.2f ms/frame   median %7.2f ms/frame   %7.1f keypoints/frame\n", name, mean, median,
                kps);
  }
};

template <typename F>
double time_ms(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: orb_benchmark <TUM folder | image folder> [--frames N]\n";
    return 2;
  }
  size_t max_frames = 0;  // 0 = all
  for (int i = 2; i < argc; ++i) {
    if (std::string(argv[i]) == "--frames" && i + 1 < argc) max_frames = std::stoul(argv[++i]);
  }
  std::vector<fs::path> images = list_images(argv[1]);
  if (max_frames > 0 && images.size() > max_frames) images.resize(max_frames);
  if (images.empty()) {
    std::cerr << "no images found in " << argv[1] << "\n";
    return 1;
  }

  const edge_slam::OrbExtractor ours;
  const cv::Ptr<cv::ORB> opencv = cv::ORB::create(1000, 1.2f, 8);
  Stats ours_stats, opencv_stats;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  size_t frame = 0;
  for (const fs::path& path : images) {
    const cv::Mat color = cv::imread(path.string(), cv::IMREAD_COLOR);
    if (color.empty()) {
      std::cerr << "skipping unreadable " << path << "\n";
      continue;
    }
    cv::Mat gray;
    cv::cvtColor(color, gray, cv::COLOR_BGR2GRAY);
    // Alternate which one runs first so cache warmth does not favour either.
    auto run_ours = [&] {
      ours_stats.ms.push_back(time_ms([&] { ours.extract(gray, keypoints, descriptors); }));
      ours_stats.counts.push_back(keypoints.size());
    };
    auto run_opencv = [&] {
      opencv_stats.ms.push_back(time_ms([&] { opencv->detectAndCompute(gray, cv::noArray(), keypoints, descriptors); }));
      opencv_stats.counts.push_back(keypoints.size());
    };
    if (frame++ % 2 == 0) {
      run_ours();
      run_opencv();
    } else {
      run_opencv();
      run_ours();
    }
  }
  if (ours_stats.ms.empty()) return 1;
  std::printf("%zu frames from %s (%d x %d)\n", ours_stats.ms.size(), argv[1], cv::imread(images[0].string()).cols,
              cv::imread(images[0].string()).rows);
  ours_stats.print("ours");
  opencv_stats.print("cv::ORB");
  const double ratio = std::accumulate(ours_stats.ms.begin(), ours_stats.ms.end(), 0.0) /
                       std::accumulate(opencv_stats.ms.begin(), opencv_stats.ms.end(), 0.0);
  std::printf("ours / cv::ORB time ratio (means): %.2f\n", ratio);
  return 0;
}
