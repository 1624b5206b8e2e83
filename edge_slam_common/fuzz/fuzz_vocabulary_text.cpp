// Fuzz target: bytes -> the vocabulary loader (ORB-SLAM2 text format, and whatever format the
// bytes claim) -> a loaded vocabulary transforms descriptors.
#include <edge_slam/io/vocabulary_io.h>

#include <stdexcept>

#include "fuzz_support.h"

using namespace edge_slam;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const BowVocabulary voc = load_vocabulary_from_bytes(data, size, "fuzz input");
    static const cv::Mat descriptors = fuzz::random_descriptors(20, 5);
    BowVector bow;
    FeatureVector features;
    voc.transform(descriptors, bow, features, 1);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
