// The split's test fixture: 60 frames rendered from the project's synthetic room (4 s of
// walking), a vocabulary trained on them, a view of the room's far side that is never mapped,
// and what an edge would send back for a list of KeyFrame records.
#pragma once
#include <opencv2/imgproc.hpp>

#include "edge_slam/data/bow_vocabulary.h"
#include "edge_slam/io/map_records.h"
#include "edge_slam/module/mobile_session.h"
#include "edge_slam/sim/renderer.h"
#include "edge_slam/sim/scene.h"
#include "edge_slam/sim/synthetic_camera.h"
#include "edge_slam/sim/trajectory.h"

namespace edge_slam {
namespace split_fixture {

constexpr int kFrames = 60;  // every 2nd pose of the sequence: 4 s of walking

struct RenderedSequence {
  PinholeCamera camera = synthetic_room_camera(30.0);
  std::vector<cv::Mat> colors, depths;
  cv::Mat elsewhere_color, elsewhere_depth;  // the far side of the room: never mapped here
  std::shared_ptr<BowVocabulary> vocabulary = std::make_shared<BowVocabulary>();

  RenderedSequence() {
    const Scene scene = Scene::build(42, 64.0);  // coarser textures: fast to build
    const Trajectory trajectory(42);
    RenderOptions options;
    options.supersample = 1;
    std::vector<cv::Mat> descriptors;
    const OrbExtractor orb;
    for (int i = 0; i < kFrames; ++i) {
      const RenderedFrame f = render(scene, camera, trajectory.pose_at(i / 15.0), options);
      cv::Mat rgb;
      cv::cvtColor(f.bgr, rgb, cv::COLOR_BGR2RGB);
      colors.push_back(rgb);
      depths.push_back(f.depth);
      if (i % 5 == 0) {
        cv::Mat gray, desc;
        std::vector<cv::KeyPoint> keys;
        cv::cvtColor(f.bgr, gray, cv::COLOR_BGR2GRAY);
        orb.extract(gray, keys, desc);
        descriptors.push_back(desc);
      }
    }
    const RenderedFrame far = render(scene, camera, trajectory.pose_at(10.0), options);
    cv::cvtColor(far.bgr, elsewhere_color, cv::COLOR_BGR2RGB);
    elsewhere_depth = far.depth;
    VocabularyParams vp;
    vp.branching = 8;
    vp.levels = 3;
    vocabulary->train(descriptors, vp);
  }
};

inline const RenderedSequence& sequence() {
  static const RenderedSequence s;
  return s;
}

// The paper's split: the mobile asks for a KeyFrame whenever conditions 3-5 hold (no edge to wait for).
inline MobileSessionParams paper_pacing(MobileSessionParams p = {}) {
  p.keyframe_pacing = MobileSessionParams::KeyFramePacing::kNone;
  return p;
}

inline MobileSession make_session(const MobileSessionParams& params = {}) {
  return MobileSession(sequence().camera, OrbParams(), TrackingParams(), sequence().vocabulary, params,
                       RgbEncoding::kRgb);
}

// A mobile as robot `robot` tracking frames [first, last) of the fixture; the records it sent.
inline std::vector<KeyFrameRecord> robot_keyframes(int robot, int first, int last) {
  const RenderedSequence& seq = sequence();
  MobileSessionParams params = paper_pacing();
  params.robot_index = robot;
  MobileSession mobile = make_session(params);
  for (int i = first; i < last; ++i) mobile.track(seq.colors[i], seq.depths[i], i / 15.0);
  std::vector<KeyFrameRecord> sent;
  while (auto r = mobile.outbox().try_pop()) sent.push_back(std::move(*r));
  return sent;
}

// What the edge would send back: every KeyFrame received so far with all its points.
inline MapUpdateRecord update_from(const std::vector<KeyFrameRecord>& sent, const PinholeCamera& camera) {
  const auto pyramid = std::make_shared<ScalePyramid>(ScalePyramid::make(8, 1.2f));
  Map global;
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  std::vector<std::shared_ptr<MapPoint>> mps;
  for (const KeyFrameRecord& r : sent) {
    kfs.push_back(keyframe_from_record(r, camera, pyramid));
    for (const NewPointRecord& p : r.new_points) mps.push_back(map_point_from_new_point(p, *kfs.back()));
  }
  global.rebuild(kfs, mps);
  MapUpdateRecord u;
  for (const auto& kf : global.keyframes()) u.keyframes.push_back(to_record(*kf, global));
  for (const auto& mp : global.map_points()) u.points.push_back(to_record(*mp));
  return u;
}

}  // namespace split_fixture
}  // namespace edge_slam
