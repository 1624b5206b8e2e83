// KeyFrameDatabase candidate selection with hand-made BoW vectors.
#include <gtest/gtest.h>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"

#include "support/blank_features.h"

using namespace edge_slam;

namespace {
std::shared_ptr<const FrameFeatures> features(size_t n) { return blank_features(n); }

// Words [first, first + count) with equal weights.
BowVector words(WordId first, WordId count) {
  BowVector v;
  for (WordId w = first; w < first + count; ++w) v[w] = 1.0 / count;
  return v;
}

std::shared_ptr<KeyFrame> add_kf(Map& map, KeyFrameDatabase& db, uint32_t id, const BowVector& bow) {
  auto kf = std::make_shared<KeyFrame>(id, id, 0.0, features(1), Eigen::Isometry3d::Identity());
  kf->set_bow(bow, {});
  map.add_keyframe(kf);
  db.add(kf);
  return kf;
}
}  // namespace

TEST(KeyFrameDatabase, RelocalizationPrefersTheMostSimilarGroup) {
  Map map;
  KeyFrameDatabase db;
  add_kf(map, db, 0, words(0, 100));
  add_kf(map, db, 1, words(50, 100));   // shares 50 with the query below
  add_kf(map, db, 2, words(85, 100));   // shares 85
  add_kf(map, db, 3, words(500, 100));  // nothing in common
  EXPECT_EQ(db.size(), 4u);

  Frame frame(0, 0.0, features(1));
  frame.set_bow(words(100, 100), {});  // words 100..199
  const auto cands = db.detect_relocalization_candidates(frame, map);
  ASSERT_FALSE(cands.empty());
  EXPECT_EQ(cands.front()->id(), 2u);
  for (const auto& kf : cands) EXPECT_NE(kf->id(), 3u);
  // 50 shared words are below 0.8 x 85: keyframe 1 is not even scored.
  for (const auto& kf : cands) EXPECT_NE(kf->id(), 1u);

  db.erase(map.keyframe(2));
  EXPECT_EQ(db.size(), 3u);
  const auto after = db.detect_relocalization_candidates(frame, map);
  ASSERT_FALSE(after.empty());
  EXPECT_EQ(after.front()->id(), 1u);
}

TEST(KeyFrameDatabase, LoopCandidatesExcludeConnectedKeyFramesAndLowScores) {
  Map map;
  KeyFrameDatabase db;
  auto a = add_kf(map, db, 0, words(0, 100));
  auto b = add_kf(map, db, 1, words(10, 100));
  auto c = add_kf(map, db, 2, words(5, 100));
  auto q = add_kf(map, db, 3, words(0, 100));
  q->add_connection(1, 30);  // the query's covisible neighbour cannot be a loop
  const auto loops = db.detect_loop_candidates(q, 0.5, map);
  ASSERT_FALSE(loops.empty());
  EXPECT_EQ(loops.front()->id(), 0u);
  for (const auto& kf : loops) {
    EXPECT_NE(kf->id(), 1u);
    EXPECT_NE(kf->id(), 3u);
  }
  EXPECT_TRUE(db.detect_loop_candidates(q, 1.01, map).empty());
  (void)a;
  (void)b;
  (void)c;
}
