// Essential-graph pose optimisation after a loop closure (RGB-D, so SE(3): scale is fixed).
// Vertices are keyframe poses; edges are relative-pose measurements (spanning tree, strong
// covisibility, previous loops: from the uncorrected poses; new loop edges: from the loop
// transform). Every edge residual is the 6-vector (2 * quaternion vector part, translation) of
// the error transform, equally weighted unless the edge says otherwise; no robust kernel.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace edge_slam {

struct PoseGraphVertex {
  uint32_t id = 0;
  Eigen::Isometry3d T_cw = Eigen::Isometry3d::Identity();  // x_c = T_cw * x_w
  bool fixed = false;  // e.g. the loop keyframe
};

struct PoseGraphEdge {
  uint32_t from_id = 0;
  uint32_t to_id = 0;
  // Measured relative pose mapping the 'from' camera frame into the 'to' camera frame:
  // ideally T_to_from == T_to_w * T_from_w^-1.
  Eigen::Isometry3d T_to_from = Eigen::Isometry3d::Identity();
  double weight = 1.0;  // scales the squared residual
};

// Builds an edge whose measurement is the current relative pose of the two keyframes.
inline PoseGraphEdge make_relative_pose_edge(uint32_t from_id, const Eigen::Isometry3d& T_from_w,
                                             uint32_t to_id, const Eigen::Isometry3d& T_to_w) {
  PoseGraphEdge e;
  e.from_id = from_id;
  e.to_id = to_id;
  e.T_to_from = T_to_w * T_from_w.inverse();
  return e;
}

struct PoseGraphProblem {
  std::vector<PoseGraphVertex> vertices;
  std::vector<PoseGraphEdge> edges;
};

struct PoseGraphOptions {
  int iterations = 20;
  int num_threads = 1;
};

struct PoseGraphResult {
  bool ok = false;
  std::string message;
  std::vector<PoseGraphVertex> vertices;  // same order as the problem, corrected (inputs on failure)
  double initial_cost = 0.0;  // sum over edges of weight * |residual|^2
  double final_cost = 0.0;
  int iterations = 0;
};

// Vertices flagged fixed stay bit-exact; when none is flagged the smallest id is held fixed.
// Edges naming unknown vertices, self-edges and edges with non-finite or non-positive data are
// skipped (counted in the message). ok=false when a vertex pose is non-finite, ids repeat, no
// usable edge touches a free vertex, or Ceres fails.
PoseGraphResult optimize_pose_graph(const PoseGraphProblem& problem,
                                    const PoseGraphOptions& options = {});

}  // namespace edge_slam
