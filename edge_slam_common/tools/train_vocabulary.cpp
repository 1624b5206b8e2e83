// Trains a bag-of-words vocabulary from image folders or TUM RGB-D sequence folders.
//   train_vocabulary --out vocab.bin [--k 10] [--levels 6] [--every N] [--max-images M]
//                    [--seed S] <inputs...>
// An input is a TUM folder (has rgb.txt; frames in its order) or a folder of images (all
// .png/.jpg/.jpeg, sorted by name). --every keeps every N-th frame of each input, --max-images
// caps the total. An --out path ending in .txt writes ORB-SLAM2's ORBvoc.txt format instead
// of our binary format.
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "edge_slam/data/bow_training_features.h"
#include "edge_slam/data/bow_training_images.h"
#include "edge_slam/data/bow_training_options.h"

using namespace edge_slam;
using Clock = std::chrono::steady_clock;

namespace {

struct Options : TrainingOptions {
  std::vector<std::string> inputs;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<std::string> selected_frames(const Options& options) {
  std::vector<std::string> selected;
  for (const std::string& input : options.inputs) {
    const std::vector<std::string> frames = list_training_images(input);
    size_t kept = 0;
    for (size_t i = 0; i < frames.size(); i += static_cast<size_t>(options.every), ++kept) selected.push_back(frames[i]);
    std::printf("%s: %zu frames, using %zu\n", input.c_str(), frames.size(), kept);
  }
  if (options.max_images >= 0 && selected.size() > static_cast<size_t>(options.max_images))
    selected.resize(static_cast<size_t>(options.max_images));
  return selected;
}

// An empty message is --help.
[[noreturn]] void usage(const std::string& message) {
  exit_with_training_usage(
      "usage: train_vocabulary --out vocab.bin [--k 10] [--levels 6] [--every N] [--max-images M]\n"
      "                        [--seed S] <image folder | TUM folder with rgb.txt>...\n",
      message);
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") usage("");
    if (arg.rfind("--", 0) == 0) {
      if (i + 1 >= argc) usage(arg + " needs a value");
      const char* value = argv[++i];
      try {
        if (!parse_training_flag(arg, value, o)) usage("unknown option " + arg);
      } catch (const std::invalid_argument& e) {
        usage(e.what());
      }
    } else {
      o.inputs.push_back(arg);
    }
  }
  if (o.out.empty()) usage("--out is required");
  if (o.inputs.empty()) usage("no inputs given");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse_options(argc, argv);
  try {
    const std::vector<std::string> frames = selected_frames(options);
    const auto start = Clock::now();
    std::vector<cv::Mat> descriptors;
    size_t total = 0;
    for (size_t i = 0; i < frames.size(); ++i) {
      const cv::Mat gray = cv::imread(frames[i], cv::IMREAD_GRAYSCALE);
      if (gray.empty()) throw std::runtime_error("cannot read image '" + frames[i] + "'");
      descriptors.push_back(extract_training_descriptors(gray));
      total += static_cast<size_t>(descriptors.back().rows);
      if ((i + 1) % 100 == 0) std::printf("  features: %zu / %zu images\n", i + 1, frames.size());
    }
    std::printf("extracted %zu descriptors from %zu images in %.1f s\n", total, frames.size(), seconds_since(start));

    train_and_save_vocabulary(descriptors, options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
