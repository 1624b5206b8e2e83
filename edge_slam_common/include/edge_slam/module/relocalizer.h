// Relocalization of a lost frame against the keyframes of a map (ORB-SLAM2 scheme):
// BoW candidates from the keyframe database, BoW matching (ratio 0.75, >= 15 matches),
// PnP RANSAC + pose-only optimisation, then guided projection searches to reach
// min_inliers (50). Kept behind its own interface so that the split system can run it
// on the edge (the paper sends relocalization frames to the edge) or on the mobile.
#pragma once
#include <memory>

#include "edge_slam/data/frame.h"
#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/keyframe_database.h"
#include "edge_slam/data/map.h"

namespace edge_slam {

class BowVocabulary;

class Relocalizer {
 public:
  virtual ~Relocalizer() = default;
  // On success sets frame's pose, matches and reference keyframe and returns true.
  virtual bool relocalize(Frame& frame) = 0;
};

class BowPnpRelocalizer : public Relocalizer {
 public:
  BowPnpRelocalizer(std::shared_ptr<const Map> map, std::shared_ptr<const KeyFrameDatabase> database,
                    std::shared_ptr<const BowVocabulary> vocabulary, int min_inliers = 50);
  bool relocalize(Frame& frame) override;

 private:
  bool try_candidate(Frame& frame, const std::shared_ptr<KeyFrame>& kf);
  std::shared_ptr<const Map> map_;
  std::shared_ptr<const KeyFrameDatabase> database_;
  std::shared_ptr<const BowVocabulary> vocabulary_;
  int min_inliers_;
};

}  // namespace edge_slam
