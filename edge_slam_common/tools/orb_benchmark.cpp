// Micro-benchmark: our OrbExtractor against cv::ORB (1000 features, scale 1.2, 8 levels),
// interleaved frame by frame in one run so both see the same machine load.
// Usage: orb_benchmark <TUM sequence folder | image folder> [--frames N] [--cv-threads N] [--match-count] [--json FILE]
// --cv-threads sets OpenCV's internal thread pool (blur/resize may use it in both extractors).
// Both wall and CPU time of the calling thread are reported; with --cv-threads 1 all the work
// is on that thread, so the CPU ratio is the battery cost and does not move with other load.
// --match-count asks cv::ORB for as many features as make its mean keypoint count on the first
// frames match ours (it returns fewer than asked for), so both do the same amount of work.
// --json writes the figures for the benchmark report (scripts/bench/speed.py).
#include <time.h>

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

double mean_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }

// How evenly keypoints cover the frame: the fullest cell of a 4x4 grid relative to an
// even share, and the fraction of 40x40-pixel cells that hold at least one keypoint.
struct Coverage {
  double fullest_over_share = 0;
  double occupied_fraction = 0;
};

Coverage coverage_of(const std::vector<cv::KeyPoint>& keypoints, const cv::Size& size) {
  Coverage c;
  if (keypoints.empty()) return c;
  std::vector<int> coarse(16, 0);
  const int fine_cols = (size.width + 39) / 40, fine_rows = (size.height + 39) / 40;
  std::vector<char> fine(static_cast<size_t>(fine_cols) * fine_rows, 0);
  for (const cv::KeyPoint& kp : keypoints) {
    const int x = std::clamp(static_cast<int>(kp.pt.x), 0, size.width - 1);
    const int y = std::clamp(static_cast<int>(kp.pt.y), 0, size.height - 1);
    ++coarse[(y * 4 / size.height) * 4 + x * 4 / size.width];
    fine[(y / 40) * fine_cols + x / 40] = 1;
  }
  c.fullest_over_share = *std::max_element(coarse.begin(), coarse.end()) / (keypoints.size() / 16.0);
  c.occupied_fraction = std::accumulate(fine.begin(), fine.end(), 0.0) / fine.size();
  return c;
}

struct Stats {
  std::vector<double> ms;
  std::vector<double> cpu_ms;
  std::vector<double> counts;
  std::vector<double> fullest_over_share;
  std::vector<double> occupied_fraction;
  void add(double elapsed_ms, double elapsed_cpu_ms, const std::vector<cv::KeyPoint>& keypoints, const cv::Size& size) {
    ms.push_back(elapsed_ms);
    cpu_ms.push_back(elapsed_cpu_ms);
    counts.push_back(static_cast<double>(keypoints.size()));
    const Coverage c = coverage_of(keypoints, size);
    fullest_over_share.push_back(c.fullest_over_share);
    occupied_fraction.push_back(c.occupied_fraction);
  }
  static double median_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  }
  void print(const char* name) const {
    std::printf("%-8s wall mean %6.2f median %6.2f ms | cpu mean %6.2f median %6.2f ms | %6.1f kp/frame  "
                "fullest 4x4 cell %.2fx share  40px cells occupied %.0f%%\n",
                name, mean_of(ms), median_of(ms), mean_of(cpu_ms), median_of(cpu_ms), mean_of(counts),
                mean_of(fullest_over_share), 100.0 * mean_of(occupied_fraction));
  }
  std::string json() const {
    char buf[512];
    std::snprintf(buf, sizeof(buf),
                  "{\"wall_mean_ms\": %.4f, \"wall_median_ms\": %.4f, \"cpu_mean_ms\": %.4f, \"cpu_median_ms\": %.4f, "
                  "\"keypoints_mean\": %.1f, \"fullest_4x4_over_share\": %.3f, \"occupied_40px\": %.3f}",
                  mean_of(ms), median_of(ms), mean_of(cpu_ms), median_of(cpu_ms), mean_of(counts),
                  mean_of(fullest_over_share), mean_of(occupied_fraction));
    return buf;
  }
};

double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// Wall and thread-CPU milliseconds of f().
template <typename F>
std::pair<double, double> time_ms(F&& f) {
  const double cpu0 = thread_cpu_ms();
  const auto start = std::chrono::steady_clock::now();
  f();
  return {std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(),
          thread_cpu_ms() - cpu0};
}

}  // namespace

int main(int argc, char** argv) {
  const bool help = argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h");
  if (argc < 2 || help) {
    std::cerr << "usage: orb_benchmark <TUM folder | image folder> [--frames N] [--cv-threads N] [--match-count] [--json FILE]\n";
    return help ? 0 : 2;
  }
  size_t max_frames = 0;  // 0 = all
  std::string json_path;
  bool match_count = false;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--frames" && i + 1 < argc) {
      max_frames = std::stoul(argv[++i]);
    } else if (arg == "--cv-threads" && i + 1 < argc) {
      cv::setNumThreads(std::stoi(argv[++i]));
    } else if (arg == "--match-count") {
      match_count = true;
    } else if (arg == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else {
      std::cerr << "unknown argument " << arg << "\n";
      return 2;
    }
  }
  std::vector<fs::path> images = list_images(argv[1]);
  if (max_frames > 0 && images.size() > max_frames) images.resize(max_frames);
  if (images.empty()) {
    std::cerr << "no images found in " << argv[1] << "\n";
    return 1;
  }

  const edge_slam::OrbExtractor ours;
  int opencv_features = 1000;
  if (match_count) {
    // Mean keypoints of both on the first frames; scale cv::ORB's request until it gives ours.
    std::vector<cv::Mat> sample;
    for (size_t k = 0; k < images.size() && sample.size() < 20; ++k) {
      cv::Mat c = cv::imread(images[k].string(), cv::IMREAD_COLOR), g;
      if (c.empty()) continue;
      cv::cvtColor(c, g, cv::COLOR_BGR2GRAY);
      sample.push_back(g);
    }
    auto mean_count = [&](auto&& extract) {
      double n = 0;
      std::vector<cv::KeyPoint> kps;
      cv::Mat desc;
      for (const cv::Mat& g : sample) {
        extract(g, kps, desc);
        n += static_cast<double>(kps.size());
      }
      return sample.empty() ? 0.0 : n / sample.size();
    };
    const double want = mean_count([&](const cv::Mat& g, auto& k, auto& d) { ours.extract(g, k, d); });
    for (int round = 0; round < 4 && want > 0; ++round) {
      const cv::Ptr<cv::ORB> probe = cv::ORB::create(opencv_features, 1.2f, 8);
      const double got = mean_count([&](const cv::Mat& g, auto& k, auto& d) { probe->detectAndCompute(g, cv::noArray(), k, d); });
      if (got <= 0 || std::abs(got - want) < 0.005 * want) break;
      opencv_features = static_cast<int>(std::lround(opencv_features * want / got));
    }
  }
  const cv::Ptr<cv::ORB> opencv = cv::ORB::create(opencv_features, 1.2f, 8);
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
      const auto [wall, cpu] = time_ms([&] { ours.extract(gray, keypoints, descriptors); });
      ours_stats.add(wall, cpu, keypoints, gray.size());
    };
    auto run_opencv = [&] {
      const auto [wall, cpu] = time_ms([&] { opencv->detectAndCompute(gray, cv::noArray(), keypoints, descriptors); });
      opencv_stats.add(wall, cpu, keypoints, gray.size());
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
  std::printf("%zu frames from %s (%d x %d), OpenCV threads %d, cv::ORB asked for %d features\n", ours_stats.ms.size(),
              argv[1], cv::imread(images[0].string()).cols, cv::imread(images[0].string()).rows, cv::getNumThreads(),
              opencv_features);
  ours_stats.print("ours");
  opencv_stats.print("cv::ORB");
  const double wall_ratio = mean_of(ours_stats.ms) / mean_of(opencv_stats.ms);
  const double cpu_ratio = mean_of(ours_stats.cpu_ms) / mean_of(opencv_stats.cpu_ms);
  std::printf("ours / cv::ORB time ratio (means): wall %.2f, cpu %.2f\n", wall_ratio, cpu_ratio);
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\"frames\": " << ours_stats.ms.size() << ", \"cv_threads\": " << cv::getNumThreads()
        << ", \"opencv_nfeatures\": " << opencv_features
        << ", \"ours\": " << ours_stats.json() << ", \"opencv\": " << opencv_stats.json()
        << ", \"ratio_wall\": " << wall_ratio << ", \"ratio_cpu\": " << cpu_ratio << "}\n";
    if (!out) {
      std::cerr << "orb_benchmark: cannot write " << json_path << "\n";
      return 1;
    }
  }
  return 0;
}
