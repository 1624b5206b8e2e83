#include "edge_slam/data/keyframe_database.h"

#include <algorithm>
#include <unordered_set>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

namespace {
constexpr double kCommonWordsRatio = 0.8;   // of the best shared-word count
constexpr double kAccumulatedRatio = 0.75;  // of the best accumulated group score
constexpr size_t kGroupSize = 10;           // covisible neighbours forming a group
}  // namespace

void KeyFrameDatabase::add(const std::shared_ptr<KeyFrame>& kf) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (indexed_.count(kf->id())) return;
  indexed_[kf->id()] = 1;
  for (const auto& word : kf->bow()) index_[word.first].push_back(kf);
}

void KeyFrameDatabase::erase(const std::shared_ptr<KeyFrame>& kf) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!indexed_.erase(kf->id())) return;
  for (const auto& word : kf->bow()) {
    auto it = index_.find(word.first);
    if (it == index_.end()) continue;
    auto& v = it->second;
    v.erase(std::remove(v.begin(), v.end(), kf), v.end());
    if (v.empty()) index_.erase(it);
  }
}

void KeyFrameDatabase::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  index_.clear();
  indexed_.clear();
}

size_t KeyFrameDatabase::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return indexed_.size();
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrameDatabase::detect(const BowVector& query,
                                                                uint32_t query_kf_id,
                                                                const std::vector<uint32_t>& excluded,
                                                                double min_score,
                                                                const Map& map) const {
  const std::unordered_set<uint32_t> skip(excluded.begin(), excluded.end());
  // 1. Keyframes sharing words with the query, with their shared-word counts.
  std::unordered_map<uint32_t, int> common;
  std::unordered_map<uint32_t, std::shared_ptr<KeyFrame>> by_id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& word : query) {
      const auto it = index_.find(word.first);
      if (it == index_.end()) continue;
      for (const auto& kf : it->second) {
        if (kf->id() == query_kf_id || skip.count(kf->id()) || kf->is_bad()) continue;
        ++common[kf->id()];
        by_id.emplace(kf->id(), kf);
      }
    }
  }
  if (common.empty()) return {};
  int max_common = 0;
  for (const auto& c : common) max_common = std::max(max_common, c.second);
  const int min_common = static_cast<int>(kCommonWordsRatio * max_common);

  // 2. Similarity score of those sharing enough words.
  std::unordered_map<uint32_t, double> score;
  for (const auto& [id, n] : common) {
    if (n <= min_common) continue;
    const double s = BowVocabulary::score(query, by_id[id]->bow());
    if (s >= min_score) score[id] = s;
  }
  if (score.empty()) return {};

  // 3. Accumulate over covisible groups; the group is represented by its best keyframe.
  double best_acc = 0;
  std::vector<std::pair<double, uint32_t>> groups;  // accumulated score, best member
  for (const auto& [id, s] : score) {
    double acc = s, best_s = s;
    uint32_t best_id = id;
    for (uint32_t nb : by_id[id]->best_covisibles(kGroupSize)) {
      const auto it = score.find(nb);
      if (it == score.end()) continue;
      acc += it->second;
      if (it->second > best_s) {
        best_s = it->second;
        best_id = nb;
      }
    }
    groups.emplace_back(acc, best_id);
    best_acc = std::max(best_acc, acc);
  }

  // 4. Keep the best member of every group scoring above 75% of the best group.
  const double min_acc = kAccumulatedRatio * best_acc;
  std::vector<std::pair<double, uint32_t>> kept;
  std::unordered_set<uint32_t> seen;
  for (const auto& [acc, id] : groups)
    if (acc > min_acc && seen.insert(id).second) kept.emplace_back(acc, id);
  std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& k : kept) {
    auto kf = map.keyframe(k.second);
    if (!kf) kf = by_id[k.second];
    if (kf && !kf->is_bad()) out.push_back(std::move(kf));
  }
  return out;
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrameDatabase::detect_relocalization_candidates(
    const Frame& frame, const Map& map) const {
  return detect(frame.bow(), kNoId, {}, 0.0, map);
}

std::vector<std::shared_ptr<KeyFrame>> KeyFrameDatabase::detect_loop_candidates(
    const std::shared_ptr<KeyFrame>& kf, double min_score, const Map& map) const {
  const auto connected = kf->ordered_neighbours();
  return detect(kf->bow(), kf->id(), connected, min_score, map);
}

}  // namespace edge_slam
