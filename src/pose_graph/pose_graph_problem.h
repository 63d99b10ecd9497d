// Internal to the pose-graph solver and its covariances: a PoseGraph
// checked and turned into dense working copies and a Ceres problem. Not
// installed.
#ifndef SYMBA_SRC_POSE_GRAPH_POSE_GRAPH_PROBLEM_H_
#define SYMBA_SRC_POSE_GRAPH_POSE_GRAPH_PROBLEM_H_

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <ceres/manifold.h>
#include <ceres/problem.h>

#include "symba/common/status.h"
#include "symba/factors/pose_graph_edge.h"
#include "symba/pose_graph/pose_graph.h"

namespace symba::internal {

struct PreparedPoseEdge {
  int a = 0;  // dense vertex indices
  int b = 0;
  Rigid3d T_ab;        // normalised
  Matrix6d sqrt_info;  // UpperCholeskyFactor(information)
  Matrix6d isotropic;  // IsotropicInformation(information)
};

struct PreparedPoseGraph {
  // The vertices that have edges, by dense index (first appearance in the
  // edge list): their ids and working copies of their poses (normalised).
  std::vector<int64_t> ids;
  std::unordered_map<int64_t, int> index_of;
  std::vector<Rigid3d> states;
  std::vector<PreparedPoseEdge> edges;
  // The gauge (by dense index): the graph's fixed vertices, plus the
  // smallest id of every connected component that has none.
  std::vector<bool> constant;
};

// Checks `graph` and prepares it. Errors (nothing prepared): an edge to a
// missing vertex or to itself, a non-finite number, a quaternion not unit
// within kQuaternionNormTolerance, an information that is not symmetric
// positive definite, a fixed vertex that does not exist.
Status PreparePoseGraph(const PoseGraph& graph, PreparedPoseGraph* prepared);

// The Ceres problem of a prepared graph: one PoseGraphEdgeFactor per edge
// on prepared->states (which must outlive it), every quaternion on the
// quaternion manifold it owns, the gauge vertices constant.
class PoseGraphProblem {
 public:
  PoseGraphProblem(PoseGraphRotationError rotation_error,
                   PreparedPoseGraph* prepared);
  PoseGraphProblem(const PoseGraphProblem&) = delete;
  PoseGraphProblem& operator=(const PoseGraphProblem&) = delete;

  ceres::Problem& problem() { return problem_; }
  // One residual block per edge, in the prepared graph's edge order.
  const std::vector<ceres::ResidualBlockId>& edge_blocks() const {
    return edge_blocks_;
  }

 private:
  // Declared before the problem, which does not own it and must not
  // outlive it.
  ceres::EigenQuaternionManifold quaternion_manifold_;
  ceres::Problem problem_;
  std::vector<ceres::ResidualBlockId> edge_blocks_;
};

}  // namespace symba::internal

#endif  // SYMBA_SRC_POSE_GRAPH_POSE_GRAPH_PROBLEM_H_
