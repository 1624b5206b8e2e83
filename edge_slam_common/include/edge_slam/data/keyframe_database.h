// Inverted index from visual words to the keyframes containing them, used to find
// relocalization and loop candidates by bag-of-words similarity (ORB-SLAM2's scheme:
// count shared words, keep keyframes sharing > 80% of the best count, score them,
// accumulate scores over covisible groups, keep groups above 75% of the best group).
#pragma once
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "edge_slam/data/bow_types.h"

namespace edge_slam {

class Frame;
class KeyFrame;
class Map;

class KeyFrameDatabase {
 public:
  void add(const std::shared_ptr<KeyFrame>& kf);  // kf must have its BoW computed
  void erase(const std::shared_ptr<KeyFrame>& kf);
  void clear();
  size_t size() const;  // number of indexed keyframes

  // `frame` must have its BoW computed. Covisibility is read through `map`.
  std::vector<std::shared_ptr<KeyFrame>> detect_relocalization_candidates(const Frame& frame,
                                                                          const Map& map) const;
  // Excludes keyframes connected to `kf` in the covisibility graph and those scoring
  // below `min_score` against it.
  std::vector<std::shared_ptr<KeyFrame>> detect_loop_candidates(const std::shared_ptr<KeyFrame>& kf,
                                                                double min_score,
                                                                const Map& map) const;

 private:
  std::vector<std::shared_ptr<KeyFrame>> detect(const BowVector& query, uint32_t query_kf_id,
                                                const std::vector<uint32_t>& excluded,
                                                double min_score, const Map& map) const;

  mutable std::mutex mutex_;
  std::unordered_map<WordId, std::vector<std::shared_ptr<KeyFrame>>> index_;
  std::unordered_map<uint32_t, int> indexed_;  // kf id -> 1
};

}  // namespace edge_slam
