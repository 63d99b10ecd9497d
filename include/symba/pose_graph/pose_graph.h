// A 3-D pose graph: vertices (poses T_w,id) and relative-pose edges with
// their information (docs/pose-graphs.md). Read from g2o files by
// symba/io/pose_graph.h, optimised by symba/pose_graph/optimize_pose_graph.h.
#ifndef SYMBA_POSE_GRAPH_POSE_GRAPH_H_
#define SYMBA_POSE_GRAPH_POSE_GRAPH_H_

#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// A relative-pose measurement between two vertices.
struct PoseGraphEdge {
  int64_t from = 0;  // vertex a
  int64_t to = 0;    // vertex b
  Rigid3d T_ab;      // measured pose of b in a's frame
  // 6 x 6 symmetric positive definite, rows/columns [translation; rotation]
  // (the error of include/symba/factors/pose_graph_edge.h).
  Matrix6d information = Matrix6d::Identity();
};

struct PoseGraph {
  std::map<int64_t, Rigid3d> poses;  // vertex id -> T_w,id
  std::vector<PoseGraphEdge> edges;  // in file order
  std::set<int64_t> fixed;           // vertices held constant (g2o FIX)
};

// SE-Sync's isotropic approximation of an edge information (the weights of
// its published optima): diag(tau I3, 2 kappa I3) with
//   tau = 3 / tr(Omega_tt^-1),  kappa = 3 / (2 tr(Omega_rr^-1)),
// Omega_tt, Omega_rr the translation and rotation diagonal blocks. With the
// rotation rows in radians (PoseGraphRotationError::kRadians) the cost of
// every state is then exactly half SE-Sync's objective (docs/pose-graphs.md).
// Returns false unless tau and kappa are finite and positive.
bool IsotropicInformation(const Matrix6d& information, Matrix6d* isotropic);

// The poses as (timestamp, T_w,id) with the vertex id as the timestamp, in
// increasing id order.
std::vector<std::pair<double, Rigid3d>> PoseGraphTrajectory(
    const PoseGraph& graph);

}  // namespace symba

#endif  // SYMBA_POSE_GRAPH_POSE_GRAPH_H_
