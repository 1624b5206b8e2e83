// What every vocabulary trainer (folder/TUM tool, bag tool) shares: the common command-line
// flags and the final train -> report -> save step, so both tools behave the same.
#pragma once
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "edge_slam/data/bow_vocabulary.h"

namespace edge_slam {

struct TrainingOptions {
  std::string out;        // .txt (any case): ORB-SLAM2's ORBvoc.txt layout; otherwise our binary format
  VocabularyParams params;
  long every = 1;         // keep every N-th image of each input
  long max_images = -1;   // cap on the total (-1: none)
};

// Applies one of the shared flags (--out --k --levels --every --max-images --seed). Returns false
// when `flag` is not one of them; throws std::invalid_argument naming the flag on a bad value.
bool parse_training_flag(const std::string& flag, const char* value, TrainingOptions& options);

// A trainer's usage text: with an empty message (--help) on stdout and exit status 0, else the
// error and the usage on stderr and exit status 2.
[[noreturn]] void exit_with_training_usage(const char* usage, const std::string& message);

// Trains on the descriptors, prints words/nodes/time and writes options.out.
void train_and_save_vocabulary(const std::vector<cv::Mat>& descriptors, const TrainingOptions& options);

}  // namespace edge_slam
