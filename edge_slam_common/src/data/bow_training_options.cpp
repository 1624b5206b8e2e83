#include "edge_slam/data/bow_training_options.h"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "edge_slam/io/vocabulary_io.h"

namespace edge_slam {
namespace {

long parse_integer(const std::string& flag, const char* text, long min) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || value < min)
    throw std::invalid_argument(flag + " expects an integer >= " + std::to_string(min) + ", got '" + text + "'");
  return value;
}

bool ends_with_txt(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".txt";
}

}  // namespace

void exit_with_training_usage(const char* usage, const std::string& message) {
  if (message.empty()) {
    std::fputs(usage, stdout);
    std::exit(0);
  }
  std::fprintf(stderr, "error: %s\n%s", message.c_str(), usage);
  std::exit(2);
}

bool parse_training_flag(const std::string& flag, const char* value, TrainingOptions& o) {
  if (flag == "--out") o.out = value;
  else if (flag == "--k") o.params.branching = static_cast<int>(parse_integer(flag, value, 2));
  else if (flag == "--levels") o.params.levels = static_cast<int>(parse_integer(flag, value, 1));
  else if (flag == "--every") o.every = parse_integer(flag, value, 1);
  else if (flag == "--max-images") o.max_images = parse_integer(flag, value, 1);
  else if (flag == "--seed") o.params.seed = static_cast<uint64_t>(parse_integer(flag, value, 0));
  else return false;
  return true;
}

void train_and_save_vocabulary(const std::vector<cv::Mat>& descriptors, const TrainingOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  BowVocabulary vocabulary;
  vocabulary.train(descriptors, o.params);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("trained k=%d L=%d: %zu words (%zu nodes) in %.1f s\n", vocabulary.branching(), vocabulary.levels(),
              vocabulary.size(), vocabulary.node_count(), seconds);
  if (ends_with_txt(o.out)) save_vocabulary_text(vocabulary, o.out);
  else save_vocabulary_binary(vocabulary, o.out);
  std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace edge_slam
