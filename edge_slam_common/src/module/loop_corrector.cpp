#include "edge_slam/module/loop_corrector.h"

#include <cmath>
#include <map>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "edge_slam/data/map_edit.h"
#include "edge_slam/match/keyframe_search.h"
#include "edge_slam/util/stopwatch.h"

namespace edge_slam {
namespace {

using PoseById = std::unordered_map<uint32_t, Eigen::Isometry3d>;

// Essential graph edges; measurements from `measured` poses except the new loop links,
// which take the corrected current poses (they are what the loop tells us).
std::vector<PoseGraphEdge> essential_edges(const Map& map, const std::vector<std::shared_ptr<KeyFrame>>& kfs,
                                           const PoseById& measured,
                                           const std::map<uint32_t, std::set<uint32_t>>& loop_links,
                                           uint32_t current_id, uint32_t loop_id, int min_weight) {
  std::vector<PoseGraphEdge> edges;
  std::set<std::pair<uint32_t, uint32_t>> inserted;
  auto key = [](uint32_t a, uint32_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  auto add = [&](uint32_t i, const Eigen::Isometry3d& Ti, uint32_t j, const Eigen::Isometry3d& Tj) {
    if (i == j || !inserted.insert(key(i, j)).second) return;
    edges.push_back(make_relative_pose_edge(i, Ti, j, Tj));
  };
  for (const auto& [i, links] : loop_links) {
    const auto ki = map.keyframe(i);
    if (!ki) continue;
    for (uint32_t j : links) {
      const auto kj = map.keyframe(j);
      if (!kj || kj->is_bad()) continue;
      if (!(i == current_id && j == loop_id) && ki->weight(j) < min_weight) continue;
      add(i, ki->T_cw(), j, kj->T_cw());
    }
  }
  for (const auto& kf : kfs) {
    const uint32_t i = kf->id();
    const Eigen::Isometry3d& Ti = measured.at(i);
    const uint32_t parent = kf->parent_id();
    if (parent != kNoId && measured.count(parent)) add(i, Ti, parent, measured.at(parent));
    for (uint32_t j : kf->loop_edges())
      if (j < i && measured.count(j)) add(i, Ti, j, measured.at(j));
    const auto children = kf->children();
    for (uint32_t j : kf->covisibles_with_weight(min_weight)) {
      if (j == parent || children.count(j) || !measured.count(j) || j > i) continue;
      add(i, Ti, j, measured.at(j));
    }
  }
  return edges;
}

}  // namespace

LoopCorrectionReport correct_loop(Map& map, const std::shared_ptr<KeyFrame>& kf, const LoopMatch& loop,
                                  const LoopCorrectionParams& params,
                                  const std::function<bool(uint32_t kf_id)>& in_map,
                                  const std::function<void(const std::function<void()>&)>& without_lock) {
  const Stopwatch t0;
  LoopCorrectionReport report;
  if (kf->is_bad() || !loop.loop_kf || loop.loop_kf->is_bad()) {
    report.message = "a keyframe of the loop went bad before correction";
    return report;
  }
  kf->update_connections(map);

  // 1. Corrected poses of the current keyframe's covisible group.
  std::vector<std::shared_ptr<KeyFrame>> group{kf};
  for (uint32_t id : kf->ordered_neighbours()) {
    auto g = map.keyframe(id);
    if (g && !g->is_bad()) group.push_back(std::move(g));
  }
  const Eigen::Isometry3d T_wc_current = kf->T_wc();
  {
    const Eigen::Isometry3d shift = loop.T_cw_corrected * T_wc_current;
    report.current_shift_m = (loop.T_cw_corrected.inverse().translation() - T_wc_current.translation()).norm();
    report.current_shift_deg = Eigen::AngleAxisd(shift.rotation()).angle() * 180.0 / M_PI;
    std::set<uint32_t> loop_side{loop.loop_kf->id()};
    for (uint32_t id : loop.loop_kf->ordered_neighbours()) loop_side.insert(id);
    for (const auto& g : group) report.group_on_loop_side += loop_side.count(g->id()) ? 1 : 0;
  }
  PoseById uncorrected, corrected;
  for (const auto& g : group) {
    uncorrected[g->id()] = g->T_cw();
    corrected[g->id()] = g == kf ? loop.T_cw_corrected : g->T_cw() * T_wc_current * loop.T_cw_corrected;
  }
  // 2. Their points move with the keyframe they are first found through.
  std::unordered_map<uint32_t, uint32_t> corrected_by;  // point id -> keyframe id
  for (const auto& g : group) {
    const Eigen::Isometry3d move = corrected[g->id()].inverse() * uncorrected[g->id()];
    for (const auto& mp : g->map_points(map)) {
      if (!mp || !corrected_by.emplace(mp->id(), g->id()).second) continue;
      mp->set_position(move * mp->position());
    }
  }
  for (const auto& g : group) g->set_pose(corrected[g->id()]);
  for (const auto& [mp_id, kf_id] : corrected_by)
    if (auto mp = map.map_point(mp_id)) mp->update_normal_and_depth(map);

  report.group_ms = t0.ms();

  // 3. Loop fusion: the verified matches, then the loop group's points into the whole group.
  // The search reads only this map's KeyFrames and points, which nothing else writes while its
  // mapping is paused, so it runs without the map lock when the caller lets it: the other
  // robots' mapping and KeyFrame arrivals go on meanwhile. The matches are applied under the
  // lock, each checked against the map as it is then. Without it (one robot) each KeyFrame's
  // search and fusion run in turn, as ORB-SLAM2's SearchAndFuse.
  FuseOptions fuse_options;
  fuse_options.th = params.fuse_window;
  fuse_options.projected_wins = true;
  fuse_options.check_reprojection = false;
  std::vector<FusionMatches> fusion;
  if (without_lock) {
    without_lock([&] {
      const Stopwatch t_search;
      for (const auto& g : group)
        if (!g->is_bad()) fusion.push_back(find_fusion_matches(g, g->T_cw(), loop.loop_points, fuse_options));
      report.fuse_search_ms = t_search.ms();
    });
  }
  const Stopwatch t_fuse;
  for (size_t i = 0; i < loop.matched.size(); ++i) {
    const auto& loop_mp = loop.matched[i];
    if (!loop_mp || loop_mp->is_bad()) continue;
    const uint32_t cur_id = kf->map_point_id(i);
    const auto cur = cur_id == kNoId ? nullptr : map.map_point(cur_id);
    if (cur && !cur->is_bad()) {
      if (cur != loop_mp) replace_map_point(map, cur, loop_mp);
    } else if (loop_mp->index_in(kf->id()) < 0) {
      add_observation(kf, i, loop_mp);
      loop_mp->update_descriptor(map);
    }
    ++report.fused_points;
  }
  if (without_lock) {
    for (const auto& m : fusion) report.fused_points += apply_fusion_matches(map, m, fuse_options);
  } else {
    for (const auto& g : group)
      if (!g->is_bad()) report.fused_points += fuse(map, g, g->T_cw(), loop.loop_points, fuse_options);
  }
  report.fuse_ms = t_fuse.ms();

  const Stopwatch t_links;
  // 4. New links created by the fusion (not within the group, not old neighbours).
  std::set<uint32_t> group_ids;
  for (const auto& g : group) group_ids.insert(g->id());
  std::map<uint32_t, std::set<uint32_t>> loop_links;
  for (const auto& g : group) {
    if (g->is_bad()) continue;
    const auto before = g->ordered_neighbours();
    g->update_connections(map);
    std::set<uint32_t> links;
    for (uint32_t id : g->ordered_neighbours()) links.insert(id);
    for (uint32_t id : before) links.erase(id);
    for (uint32_t id : group_ids) links.erase(id);
    if (!links.empty()) loop_links[g->id()] = links;
    report.new_loop_links += static_cast<int>(links.size());
  }
  loop_links[kf->id()].insert(loop.loop_kf->id());

  report.links_ms = t_links.ms();
  // 5. Essential graph over the map's keyframes, loop keyframe fixed.
  std::vector<std::shared_ptr<KeyFrame>> kfs;
  for (auto& k : map.keyframes())
    if (!k->is_bad() && (!in_map || in_map(k->id()))) kfs.push_back(std::move(k));
  PoseById measured, before_graph;
  PoseGraphProblem problem;
  for (const auto& k : kfs) {
    const Eigen::Isometry3d T = k->T_cw();
    before_graph[k->id()] = T;
    const auto it = uncorrected.find(k->id());
    measured[k->id()] = it != uncorrected.end() ? it->second : T;
    PoseGraphVertex v;
    v.id = k->id();
    v.T_cw = T;
    v.fixed = k->id() == loop.loop_kf->id();
    problem.vertices.push_back(v);
  }
  problem.edges = essential_edges(map, kfs, measured, loop_links, kf->id(), loop.loop_kf->id(),
                                  params.essential_min_weight);
  report.graph_edges = static_cast<int>(problem.edges.size());
  report.graph_keyframes = static_cast<int>(problem.vertices.size());
  const Stopwatch t_graph;
  const PoseGraphResult graph = optimize_pose_graph(problem, params.pose_graph);
  report.graph_ms = t_graph.ms();
  report.graph_initial_cost = graph.initial_cost;
  report.graph_final_cost = graph.final_cost;
  const Stopwatch t_follow;
  if (graph.ok) {
    PoseById after;
    for (const auto& v : graph.vertices) after[v.id] = v.T_cw;
    for (const auto& k : kfs) k->set_pose(after[k->id()]);
    // 6. Points follow their correcting (else reference, else any observing) keyframe. Only
    // this map's points (those its KeyFrames see) can have one: the other maps' points are not
    // visited. A keyframe the graph left where it was moves nothing; each point of the map gets
    // its normal and depth range again. When the graph moved no keyframe (a merge: it starts at
    // its optimum) only the loop side's points gained observers since step 2 refreshed the
    // group's: only they need it.
    std::unordered_set<uint32_t> moved;
    // The graph hands poses back through a quaternion: one it left alone differs by rounding.
    const auto differs = [](const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
      return (a.translation() - b.translation()).norm() > 1e-9 ||
             Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() > 1e-9;
    };
    for (const auto& k : kfs)
      if (differs(after[k->id()], before_graph[k->id()])) moved.insert(k->id());
    if (moved.empty()) {
      for (const auto* points : {&loop.loop_points, &loop.matched})
        for (const auto& mp : *points)
          if (mp && !mp->is_bad()) mp->update_normal_and_depth(map);
    } else {
      std::unordered_set<uint32_t> seen;
      for (const auto& k : kfs)
        for (uint32_t id : k->map_point_ids()) {
          if (id == kNoId || !seen.insert(id).second) continue;
          const auto mp = map.map_point(id);
          if (!mp || mp->is_bad()) continue;
          uint32_t ref = kNoId;
          const auto cb = corrected_by.find(mp->id());
          if (cb != corrected_by.end() && after.count(cb->second)) ref = cb->second;
          if (ref == kNoId && after.count(mp->reference_kf_id())) ref = mp->reference_kf_id();
          if (ref == kNoId)
            for (const auto& [obs_kf, idx] : mp->observations())
              if (after.count(obs_kf)) {
                ref = obs_kf;
                break;
              }
          if (ref == kNoId) continue;
          if (moved.count(ref)) mp->set_position(after[ref].inverse() * (before_graph[ref] * mp->position()));
          mp->update_normal_and_depth(map);
        }
    }
  }
  report.follow_ms = t_follow.ms();
  kf->add_loop_edge(loop.loop_kf->id());
  loop.loop_kf->add_loop_edge(kf->id());
  report.group_keyframes = static_cast<int>(group.size());
  report.ok = graph.ok;
  report.message = graph.ok ? "essential graph: " + graph.message
                            : "essential graph failed (" + graph.message + "); group correction kept";
  report.total_ms = t0.ms();
  return report;
}

}  // namespace edge_slam
