// Measures vocabulary file and lookup speed.
//   vocabulary_benchmark [--k 10] [--levels 6] [--out /tmp/random_vocab.bin] [--text]
//     builds a complete random tree (k=10, L=6: 1M words), saves it, and times loading it
//     (and, with --text, the same through the ORBvoc.txt format) and transforming frames.
//   vocabulary_benchmark --vocab voc.bin|ORBvoc.txt [--frames FOLDER [--every N]]
//     times loading an existing vocabulary and transforming random frames with it; with
//     --frames (image or TUM folder) also real ORB frames, and prints BoW scores between
//     neighbouring frames vs. frames far apart (a quick place-recognition sanity check).
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "edge_slam/data/bow_training_features.h"
#include "edge_slam/data/bow_training_images.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/feature/descriptor_distance.h"
#include "edge_slam/io/vocabulary_io.h"

using namespace edge_slam;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

BowTreeArrays random_complete_tree(int k, int levels, std::mt19937_64& rng) {
  BowTreeArrays tree;
  tree.branching = k;
  tree.levels = levels;
  tree.parents.push_back(BowTreeArrays::kNoParent);
  tree.is_leaf.push_back(0);
  size_t level_begin = 0, level_end = 1;
  for (int depth = 1; depth <= levels; ++depth) {
    for (size_t parent = level_begin; parent < level_end; ++parent)
      for (int c = 0; c < k; ++c) {
        tree.parents.push_back(static_cast<uint32_t>(parent));
        tree.is_leaf.push_back(depth == levels);
      }
    level_begin = level_end;
    level_end = tree.parents.size();
  }
  tree.descriptors.resize(tree.node_count() * kDescriptorBytes);
  for (auto& b : tree.descriptors) b = static_cast<uint8_t>(rng());
  std::uniform_real_distribution<double> weight(0.1, 8.0);
  tree.weights.resize(tree.node_count());
  for (size_t i = 0; i < tree.node_count(); ++i) tree.weights[i] = tree.is_leaf[i] ? weight(rng) : 0.0;
  return tree;
}

void benchmark_load(const std::string& path, const char* label) {
  const auto start = Clock::now();
  const BowVocabulary loaded = load_vocabulary(path);
  const double load_s = seconds_since(start);
  std::printf("%-6s load: %.3f s  (%zu words, %zu nodes, %.1f MB file)\n", label, load_s, loaded.size(),
              loaded.node_count(), std::filesystem::file_size(path) / 1e6);
}

void benchmark_transform(const BowVocabulary& vocabulary, std::mt19937_64& rng) {
  constexpr int kFeatures = 1000, kFrames = 50;
  cv::Mat frame(kFeatures, kDescriptorBytes, CV_8U);
  BowVector bow;
  FeatureVector features;
  double total_s = 0;
  for (int f = 0; f < kFrames; ++f) {
    for (int r = 0; r < kFeatures; ++r)
      for (int c = 0; c < kDescriptorBytes; ++c) frame.at<uint8_t>(r, c) = static_cast<uint8_t>(rng());
    const auto start = Clock::now();
    vocabulary.transform(frame, bow, features, 4);
    total_s += seconds_since(start);
  }
  std::printf("transform (BowVector + FeatureVector, levels_up 4): %.3f ms per %d-feature frame\n",
              1e3 * total_s / kFrames, kFeatures);
}

void benchmark_frames(const BowVocabulary& vocabulary, const std::string& input, int every) {
  const std::vector<std::string> files = list_training_images(input);
  std::vector<BowVector> bows;
  double transform_s = 0;
  size_t features = 0;
  for (size_t i = 0; i < files.size(); i += static_cast<size_t>(every)) {
    const cv::Mat gray = cv::imread(files[i], cv::IMREAD_GRAYSCALE);
    if (gray.empty()) throw std::runtime_error("cannot read image '" + files[i] + "'");
    const cv::Mat descriptors = extract_training_descriptors(gray);
    BowVector bow;
    FeatureVector direct;
    const auto start = Clock::now();
    vocabulary.transform(descriptors, bow, direct, 4);
    transform_s += seconds_since(start);
    features += static_cast<size_t>(descriptors.rows);
    bows.push_back(std::move(bow));
  }
  const size_t n = bows.size();
  std::printf("%zu frames of %s, %.0f features each: transform %.3f ms per frame\n", n, input.c_str(),
              static_cast<double>(features) / n, 1e3 * transform_s / n);
  double near_sum = 0, far_sum = 0;
  size_t near_count = 0, far_count = 0, best_is_neighbour = 0;
  const size_t far_gap = std::max<size_t>(n / 4, 2);
  for (size_t i = 0; i < n; ++i) {
    double best = -1;
    size_t best_j = i;
    for (size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double s = BowVocabulary::score(bows[i], bows[j]);
      if (s > best) best = s, best_j = j;
      const size_t gap = i > j ? i - j : j - i;
      if (j > i && gap == 1) near_sum += s, ++near_count;
      if (j > i && gap >= far_gap) far_sum += s, ++far_count;
    }
    best_is_neighbour += (best_j + 2 >= i && best_j <= i + 2);
  }
  std::printf("score of consecutive frames: mean %.3f; of frames >= %zu apart: mean %.3f\n",
              near_count ? near_sum / near_count : 0.0, far_gap, far_count ? far_sum / far_count : 0.0);
  std::printf("best-scoring other frame within +-2 frames: %zu of %zu\n", best_is_neighbour, n);
}

// nullptr = --help: the usage on stdout, exit status 0.
int usage(const char* message) {
  const char* text = "usage: vocabulary_benchmark [--k 10] [--levels 6] [--out FILE] [--text]\n"
                     "       vocabulary_benchmark --vocab FILE [--frames FOLDER [--every N]]\n";
  if (!message) return std::fputs(text, stdout), 0;
  std::fprintf(stderr, "error: %s\n%s", message, text);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int k = 10, levels = 6;
  bool text = false;
  std::string out = (std::filesystem::temp_directory_path() / "edge_slam_random_vocabulary.bin").string();
  std::string existing, frames;
  int every = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "-h" || arg == "--help") return usage(nullptr);
    if (arg == "--k" && has_value) k = std::atoi(argv[++i]);
    else if (arg == "--levels" && has_value) levels = std::atoi(argv[++i]);
    else if (arg == "--out" && has_value) out = argv[++i];
    else if (arg == "--vocab" && has_value) existing = argv[++i];
    else if (arg == "--frames" && has_value) frames = argv[++i];
    else if (arg == "--every" && has_value) every = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--text") text = true;
    else return usage(("unknown or incomplete argument '" + arg + "'").c_str());
  }
  try {
    std::mt19937_64 rng(1);
    if (!existing.empty()) {
      benchmark_load(existing, "given");
      const BowVocabulary vocabulary = load_vocabulary(existing);
      benchmark_transform(vocabulary, rng);
      if (!frames.empty()) benchmark_frames(vocabulary, frames, every);
      return 0;
    }
    if (k < 2 || levels < 1 || levels > 7) return usage("need k >= 2 and 1 <= levels <= 7");
    auto start = Clock::now();
    const BowVocabulary vocabulary = BowVocabulary::from_arrays(random_complete_tree(k, levels, rng));
    std::printf("built random k=%d L=%d vocabulary: %zu words in %.3f s\n", k, levels, vocabulary.size(),
                seconds_since(start));
    start = Clock::now();
    save_vocabulary_binary(vocabulary, out);
    std::printf("binary save: %.3f s -> %s\n", seconds_since(start), out.c_str());
    benchmark_load(out, "binary");
    if (text) {
      const std::string text_path = out + ".txt";
      start = Clock::now();
      save_vocabulary_text(vocabulary, text_path);
      std::printf("text save: %.3f s -> %s\n", seconds_since(start), text_path.c_str());
      benchmark_load(text_path, "text");
      std::filesystem::remove(text_path);
    }
    benchmark_transform(vocabulary, rng);
    std::filesystem::remove(out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
