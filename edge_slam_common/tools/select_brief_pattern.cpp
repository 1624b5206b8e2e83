// Re-selects the rotated-BRIEF test table (src/feature/brief_pattern.cpp) with the greedy
// low-correlation search of the ORB paper, on oriented keypoints our own extractor finds in
// images the project makes itself (the edge_slam_synth sequence, synthetic textures).
//
// Usage: select_brief_pattern [--tum <folder>] [--every N] [--texture-seeds s1,s2,...]
//            [--candidates N] [--seed S] [--min-separation PX] [--start-threshold T]
//            [--threshold-step D] --out pattern.inc
//   --tum              TUM-layout folder (rgb.txt); every N-th listed image is used (default 10)
//   --texture-seeds    also use make_synthetic_texture(640x480, seed) for each seed
//   --candidates       candidate tests drawn (default 60000)
//   --seed             SplitMix64 seed of the candidates (default 0x0DDBA11C0FFEE123)
//   --min-separation   minimum distance between the two points of a test, px (default 2)
//   --start-threshold  first |correlation| bound tried (default 0.20), --threshold-step 0.02
// Writes the kBriefTests rows in brief_pattern.cpp's initializer format, preceded by comment
// lines recording the command line and the selection statistics. Deterministic: the same
// inputs and arguments give a byte-identical file.
// Never point it at data the project may not commit derivatives of (e.g. TUM sequences).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../src/feature/brief_selection.h"
#include "edge_slam/feature/synthetic_texture.h"
#include "edge_slam/io/tum_dataset.h"

using namespace edge_slam;

namespace {

int usage() {
  std::cerr << "usage: select_brief_pattern [--tum <folder>] [--every N] [--texture-seeds s1,s2,...]\n"
               "         [--candidates N] [--seed S] [--min-separation PX] [--start-threshold T]\n"
               "         [--threshold-step D] --out pattern.inc\n";
  return 2;
}

std::vector<uint64_t> parse_seeds(const std::string& list) {
  std::vector<uint64_t> seeds;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) seeds.push_back(std::stoull(item, nullptr, 0));
  return seeds;
}

}  // namespace

int main(int argc, char** argv) {
  std::string tum_folder, out_path;
  int every = 10, candidates = 60000, min_separation = 2;
  uint64_t seed = 0x0DDBA11C0FFEE123ull;
  std::vector<uint64_t> texture_seeds;
  double start_threshold = 0.20, threshold_step = 0.02;
  std::string command_line = "select_brief_pattern";
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "-h" || arg == "--help") return usage(), 0;
      if (i + 1 >= argc) return usage();
      const std::string value = argv[++i];
      command_line += " " + arg + " " + value;
      if (arg == "--tum") tum_folder = value;
      else if (arg == "--every") every = std::stoi(value);
      else if (arg == "--texture-seeds") texture_seeds = parse_seeds(value);
      else if (arg == "--candidates") candidates = std::stoi(value);
      else if (arg == "--seed") seed = std::stoull(value, nullptr, 0);
      else if (arg == "--min-separation") min_separation = std::stoi(value);
      else if (arg == "--start-threshold") start_threshold = std::stod(value);
      else if (arg == "--threshold-step") threshold_step = std::stod(value);
      else if (arg == "--out") out_path = value;
      else return usage();
    }
  } catch (const std::exception&) {
    return usage();
  }
  if (out_path.empty() || (tum_folder.empty() && texture_seeds.empty()) || every < 1 || candidates < kBriefTests ||
      threshold_step <= 0 || start_threshold < 0)
    return usage();

  try {
    const OrbExtractor extractor;  // default parameters, as the system uses them
    SteeredSamples samples;
    size_t images = 0, mismatches = 0;
    auto add = [&](const cv::Mat& gray, const std::string& name) {
      mismatches += append_steered_samples(extractor, gray, samples);
      ++images;
      std::fprintf(stderr, "\r%zu images, %zu keypoints (%s)   ", images, samples.size(), name.c_str());
    };
    if (!tum_folder.empty()) {
      const std::vector<TumListEntry> list = read_tum_list(tum_folder + "/rgb.txt");
      for (size_t i = 0; i < list.size(); i += every) {
        const std::string path = tum_folder + "/" + list[i].path;
        const cv::Mat color = cv::imread(path, cv::IMREAD_COLOR);
        if (color.empty()) throw std::runtime_error("cannot read " + path);
        cv::Mat gray;
        cv::cvtColor(color, gray, cv::COLOR_BGR2GRAY);
        add(gray, list[i].path);
      }
    }
    for (uint64_t s : texture_seeds) add(make_synthetic_texture(cv::Size(640, 480), s), "texture " + std::to_string(s));
    std::fprintf(stderr, "\n");
    if (mismatches)
      throw std::runtime_error(std::to_string(mismatches) +
                               " keypoints: resampled descriptor differs from the extractor's; "
                               "brief_selection.cpp no longer mirrors orb_extractor.cpp / rotated_brief.cpp");

    const std::vector<BriefTest> pool = draw_candidate_tests(candidates, seed, min_separation);
    BriefSelectionParams params;
    params.threshold_step = threshold_step;
    params.start_threshold_steps = static_cast<int>(std::lround(start_threshold / threshold_step));
    const BriefSelectionResult result = select_brief_tests(samples, pool, params);

    double mean_ones = 0, worst_ones = 0.5;
    for (double p : result.ones_fraction) {
      mean_ones += p / result.ones_fraction.size();
      if (std::abs(p - 0.5) > std::abs(worst_ones - 0.5)) worst_ones = p;
    }
    std::ostringstream stats;
    stats << "// " << command_line << "\n"
          << "// " << images << " images, " << result.keypoints << " keypoints (descriptor self-check passed), "
          << candidates << " candidates; |correlation| threshold " << result.threshold << " (tried:";
    for (size_t i = 0; i < result.tried_steps.size(); ++i)
      stats << " " << result.tried_steps[i] * threshold_step << "->" << result.kept_at_step[i];
    stats << "); max |correlation| of kept pairs " << result.max_abs_correlation << "; P(bit=1) mean " << mean_ones
          << ", furthest from 0.5: " << worst_ones << "\n";

    std::ofstream out(out_path);
    if (!out) throw std::runtime_error("cannot write " + out_path);
    out << stats.str();
    for (size_t i = 0; i < result.tests.size(); ++i) {
      const BriefTest& t = result.tests[i];
      out << (i % 8 == 0 ? "    " : " ") << "{" << int(t.x1) << "," << int(t.y1) << "," << int(t.x2) << ","
          << int(t.y2) << "},";
      if (i % 8 == 7 || i + 1 == result.tests.size()) out << "\n";
    }
    if (!out) throw std::runtime_error("error writing " + out_path);
    std::cerr << stats.str();
  } catch (const std::exception& e) {
    std::cerr << "select_brief_pattern: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
