// Optimising a 3-D pose graph with Ceres (docs/pose-graphs.md).
#ifndef SYMBA_POSE_GRAPH_OPTIMIZE_POSE_GRAPH_H_
#define SYMBA_POSE_GRAPH_OPTIMIZE_POSE_GRAPH_H_

#include <string>

#include "symba/common/status.h"
#include "symba/factors/pose_graph_edge.h"
#include "symba/pose_graph/pose_graph.h"

namespace symba {

// Where Levenberg-Marquardt starts.
enum class PoseGraphInitialization {
  // chordal_initialization.h: from the measurements alone, where that
  // costs less than the graph's own poses (a solved graph keeps them)
  kChordal,
  kGiven,  // the graph's own poses (a g2o file's vertices)
};

struct PoseGraphSolveOptions {
  PoseGraphInitialization initialization = PoseGraphInitialization::kChordal;
  int max_iterations = 100;
  int num_threads = 1;
  // Ceres's convergence tolerances (ceres::Solver::Options).
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  PoseGraphRotationError rotation_error = PoseGraphRotationError::kRadians;

  Status Validate() const;
};

struct PoseGraphSolveSummary {
  // 1/2 sum of r^T r as Ceres reports it, at the given poses and where
  // Levenberg-Marquardt started (after the chordal initialisation; the same
  // with kGiven).
  double given_cost = 0.0;
  double initial_cost = 0.0;
  double initialization_seconds = 0.0;  // the chordal initialisation's
  bool chordal_start = false;           // started from the chordal guess
  double final_cost = 0.0;
  int iterations = 0;      // Levenberg-Marquardt iterations (accepted or
                           // not), not counting Ceres's iteration 0
  bool converged = false;  // Ceres terminated with CONVERGENCE
  double seconds = 0.0;    // Ceres's total solve time
  int num_vertices = 0;    // vertices with at least one edge
  int num_edges = 0;
  std::string message;  // Ceres's termination message
};

// Optimises the poses of *graph with Levenberg-Marquardt (sparse normal
// Cholesky), one PoseGraphEdgeFactor per edge, from the chordal
// initialisation (options.initialization) or the graph's own poses. Gauge: the vertices in
// graph->fixed are held constant; every connected component of the edge
// graph that contains none of them has its smallest vertex id held
// constant (for a connected graph without FIX: the smallest id). Vertices
// without edges are not touched.
//
// Returns an error, leaving *graph unchanged, if the graph is invalid (an
// edge to a missing vertex or to itself, a non-finite number, a quaternion
// not unit within 1e-3, an information that is not positive definite) or if
// Ceres fails. Otherwise writes the optimised poses of the free vertices
// back (held vertices keep their stored values bit for bit), also when the
// iteration limit is reached (summary->converged is false then).
Status OptimizePoseGraph(const PoseGraphSolveOptions& options,
                         PoseGraph* graph,
                         PoseGraphSolveSummary* summary);

}  // namespace symba

#endif  // SYMBA_POSE_GRAPH_OPTIMIZE_POSE_GRAPH_H_
