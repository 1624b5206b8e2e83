// Vocabulary training: hierarchical k-means built breadth-first (so node ids come out in the
// order the file formats use), then idf weights counted by descending every training image.
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "edge_slam/data/bow_kmeans.h"
#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/feature/descriptor_distance.h"

namespace edge_slam {
namespace {

void check_training_input(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyParams& params) {
  if (params.branching < 2)
    throw std::invalid_argument("BowVocabulary::train: branching must be >= 2, got " + std::to_string(params.branching));
  if (params.levels < 1)
    throw std::invalid_argument("BowVocabulary::train: levels must be >= 1, got " + std::to_string(params.levels));
  if (params.max_iterations < 1)
    throw std::invalid_argument("BowVocabulary::train: max_iterations must be >= 1");
  size_t total = 0;
  for (size_t i = 0; i < descriptors_per_image.size(); ++i) {
    const cv::Mat& d = descriptors_per_image[i];
    if (d.empty()) continue;
    if (d.type() != CV_8UC1 || d.cols != kDescriptorBytes)
      throw std::invalid_argument("BowVocabulary::train: image " + std::to_string(i) + " has " +
                                  std::to_string(d.rows) + " x " + std::to_string(d.cols) +
                                  " descriptors of OpenCV type " + std::to_string(d.type()) + ", expected N x " +
                                  std::to_string(kDescriptorBytes) + " CV_8UC1");
    total += static_cast<size_t>(d.rows);
  }
  if (total == 0) throw std::invalid_argument("BowVocabulary::train: no training descriptors");
  if (total >= BowTreeArrays::kNoParent / 2)
    throw std::invalid_argument("BowVocabulary::train: too many descriptors (" + std::to_string(total) + ")");
}

// All descriptors in one contiguous buffer; training permutes it so each node's rows are a range.
std::vector<uint8_t> pool_descriptors(const std::vector<cv::Mat>& descriptors_per_image) {
  std::vector<uint8_t> pool;
  for (const cv::Mat& d : descriptors_per_image)
    for (int r = 0; r < d.rows; ++r) pool.insert(pool.end(), d.ptr<uint8_t>(r), d.ptr<uint8_t>(r) + kDescriptorBytes);
  return pool;
}

struct PendingNode {
  uint32_t node;
  size_t begin, end;  // row range in the pool
  int depth;
};

BowTreeArrays build_tree(std::vector<uint8_t>& pool, const VocabularyParams& params) {
  BowTreeArrays tree;
  tree.branching = params.branching;
  tree.levels = params.levels;
  tree.parents.push_back(BowTreeArrays::kNoParent);
  tree.descriptors.assign(kDescriptorBytes, 0);
  tree.is_leaf.push_back(0);

  std::mt19937_64 rng(params.seed);
  std::vector<uint8_t> scratch(pool.size());
  std::vector<PendingNode> queue{{0, 0, pool.size() / kDescriptorBytes, 0}};
  for (size_t head = 0; head < queue.size(); ++head) {
    const PendingNode p = queue[head];
    const size_t rows = p.end - p.begin;
    uint8_t* data = pool.data() + p.begin * kDescriptorBytes;
    // The root must split; below it, single rows and the depth limit make leaves.
    if (p.node != 0 && (p.depth == params.levels || rows <= 1)) {
      tree.is_leaf[p.node] = 1;
      continue;
    }
    BinaryClusters clusters = cluster_binary_descriptors(data, rows, params.branching, params.max_iterations, rng);
    if (p.node != 0 && clusters.cluster_count() <= 1) {  // identical rows: splitting would only chain
      tree.is_leaf[p.node] = 1;
      continue;
    }
    // Stable counting sort of the node's rows by cluster, so each child owns a sub-range.
    const size_t count = clusters.cluster_count();
    std::vector<size_t> offset(count + 1, 0);
    for (uint32_t c : clusters.assignment) ++offset[c + 1];
    for (size_t c = 0; c < count; ++c) offset[c + 1] += offset[c];
    std::vector<size_t> fill(offset.begin(), offset.end() - 1);
    for (size_t i = 0; i < rows; ++i)
      std::memcpy(&scratch[fill[clusters.assignment[i]]++ * kDescriptorBytes], data + i * kDescriptorBytes,
                  kDescriptorBytes);
    std::memcpy(data, scratch.data(), rows * kDescriptorBytes);

    for (size_t c = 0; c < count; ++c) {
      const uint32_t child = static_cast<uint32_t>(tree.parents.size());
      tree.parents.push_back(p.node);
      tree.descriptors.insert(tree.descriptors.end(), clusters.centroids.begin() + c * kDescriptorBytes,
                              clusters.centroids.begin() + (c + 1) * kDescriptorBytes);
      tree.is_leaf.push_back(0);
      queue.push_back({child, p.begin + offset[c], p.begin + offset[c + 1], p.depth + 1});
    }
  }
  tree.weights.assign(tree.parents.size(), 0.0);
  return tree;
}

}  // namespace

void BowVocabulary::train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyParams& params) {
  check_training_input(descriptors_per_image, params);
  std::vector<uint8_t> pool = pool_descriptors(descriptors_per_image);
  BowVocabulary trained = from_arrays(build_tree(pool, params));
  pool = {};

  // idf(w) = log(N / n_w): N training images with descriptors, n_w of them containing word w.
  std::vector<uint32_t> images_with_word(trained.size(), 0);
  std::vector<uint32_t> last_image(trained.size(), kNotAWord);
  uint32_t image_count = 0;
  for (const cv::Mat& d : descriptors_per_image) {
    if (d.empty()) continue;
    for (int r = 0; r < d.rows; ++r) {
      const WordId w = trained.node_word_[trained.descend(d.ptr<uint8_t>(r), 0, nullptr)];
      if (last_image[w] != image_count) {
        last_image[w] = image_count;
        ++images_with_word[w];
      }
    }
    ++image_count;
  }
  for (WordId w = 0; w < trained.size(); ++w) {
    // A word no training image reaches (rare tie effects) is treated as maximally rare.
    const double n_w = images_with_word[w] > 0 ? images_with_word[w] : 1.0;
    trained.word_weight_[w] = std::log(static_cast<double>(image_count) / n_w);
  }
  *this = std::move(trained);
}

}  // namespace edge_slam
