// Test helper: what a mobile would have sent the edge for the six KeyFrames of SyntheticMap
// (records in order, each with the points it was first to see), a vocabulary trained on them,
// and edge settings without Loop-Closing (six KeyFrames close no loop).
#pragma once
#include <unordered_set>
#include <vector>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/module/edge_session.h"
#include "record_map.h"

namespace edge_slam {
namespace test_support {

struct SentKeyFrames {
  SyntheticMap source;
  std::shared_ptr<BowVocabulary> vocabulary = std::make_shared<BowVocabulary>();
  std::vector<KeyFrameRecord> sent;  // in order, seq 1, 2, ...

  SentKeyFrames() {
    std::vector<cv::Mat> descriptors;
    for (const auto& kf : source.map.keyframes()) descriptors.push_back(kf->features().descriptors);
    VocabularyParams vp;
    vp.branching = 10;  // words specific to few KeyFrames: non-zero idf weights
    vp.levels = 3;
    vocabulary->train(descriptors, vp);
    std::unordered_set<uint32_t> known;
    for (const auto& kf : source.map.keyframes()) {
      std::unordered_set<uint32_t> created;
      for (uint32_t id : kf->map_point_ids())
        if (known.insert(id).second) created.insert(id);
      KeyFrameRecord r = to_record(*kf, source.map, created);
      r.seq = sent.size() + 1;
      sent.push_back(r);
    }
  }
  EdgeSessionParams params() const {
    EdgeSessionParams p;
    p.loop_closing = false;
    return p;
  }
};

}  // namespace test_support
}  // namespace edge_slam
