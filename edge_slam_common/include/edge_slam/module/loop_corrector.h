// Loop correction (ORB-SLAM2's CorrectLoop with SE(3) instead of Sim(3), RGB-D): the current
// keyframe's covisible group and their points are moved by the verified loop transform,
// duplicates with the loop side are fused (loop points win), the new loop links are found,
// the essential graph (spanning tree + covisibility >= 100 + previous loop edges + new loop
// links; loop keyframe fixed) is optimised, and every other map point follows the keyframe
// it was corrected with (else its reference keyframe). Finally the loop edge is recorded.
// With several maps in one (several robots), only the corrected map's KeyFrames are in the graph
// and move: the other robots' maps are left as they are.
// The caller has paused local mapping for that map and holds Map::update_mutex(); if it passes
// `without_lock`, the fusion's search (reads only) is handed to it to run with the mutex released
// (see correct_loop).
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "edge_slam/data/keyframe.h"
#include "edge_slam/data/map.h"
#include "edge_slam/module/loop_verifier.h"
#include "edge_slam/optimize/pose_graph.h"

namespace edge_slam {

struct LoopCorrectionParams {
  int essential_min_weight = 100;  // covisibility edges in the essential graph (ORB-SLAM2: 100)
  float fuse_window = 4.f;         // ORB-SLAM2 loop SearchAndFuse: 4
  PoseGraphOptions pose_graph;
};

struct LoopCorrectionReport {
  bool ok = false;
  std::string message;
  int group_keyframes = 0;
  int fused_points = 0;
  int new_loop_links = 0;
  int graph_edges = 0;
  double graph_initial_cost = 0, graph_final_cost = 0;
  // How far the loop moves the current keyframe (its camera centre, its rotation): the drift the
  // loop claims. Compared with the drift the online poses show, it tells a wrong loop transform.
  double current_shift_m = 0, current_shift_deg = 0;
  // Keyframes of the current keyframe's covisible group that are also the loop keyframe or its
  // covisibles: moved as "current side" although they belong to the loop side.
  int group_on_loop_side = 0;
  int graph_keyframes = 0;
  // Time spent by phase: moving the current group (steps 1-2), applying the fusion (3), finding
  // the new links (4), the essential graph's optimisation (5), the points following their
  // KeyFrames (6); and all of it. The caller holds the map lock throughout but for the search.
  double group_ms = 0, fuse_ms = 0, links_ms = 0, graph_ms = 0, follow_ms = 0, total_ms = 0;
  // The fusion's search for matches (step 3) when handed to without_lock (outside the lock,
  // inside total_ms); 0 otherwise (inside fuse_ms).
  double fuse_search_ms = 0;
};

// in_map: the KeyFrames of the map being corrected (unset: every KeyFrame).
// without_lock(work): called once, after the group has been moved (steps 1-2), with the fusion's
// search; it releases the caller's Map::update_mutex(), runs work, and takes the mutex again, so
// the other robots' mapping is not held up by the search. Unset: each group KeyFrame's search
// and fusion run in turn (fuse()), as before and as ORB-SLAM2 (fuse_search_ms then stays 0).
LoopCorrectionReport correct_loop(Map& map, const std::shared_ptr<KeyFrame>& kf, const LoopMatch& loop,
                                  const LoopCorrectionParams& params = {},
                                  const std::function<bool(uint32_t kf_id)>& in_map = {},
                                  const std::function<void(const std::function<void()>&)>& without_lock = {});

}  // namespace edge_slam
