// 3-D pose graphs in the g2o text format (docs/pose-graphs.md): reading,
// optimising with Ceres, and writing the optimised poses as a TUM trajectory.
//
//   PoseGraph graph;
//   Status s = ReadG2oPoseGraph("parking-garage.g2o", &graph);
//   PoseGraphSolveSummary summary;
//   if (s.ok()) s = OptimizePoseGraph(PoseGraphSolveOptions(), &graph,
//                                     &summary);
//   if (s.ok()) s = WriteTumTrajectory("trajectory.tum",
//                                      PoseGraphTrajectory(graph));
//
// Every error about a file has the form "FILE:LINE: what is wrong" (LINE
// 1-based), or "FILE: what is wrong" when it concerns no single line.
#ifndef SYMBA_IO_POSE_GRAPH_H_
#define SYMBA_IO_POSE_GRAPH_H_

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "symba/common/status.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/pose_graph_edge.h"
#include "symba/geometry/rigid3.h"
#include "symba/io/tum_trajectory.h"

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

struct G2oReadOptions {
  // Replace every edge's information by IsotropicInformation() of it. This
  // also accepts information matrices that are not positive definite as long
  // as tau and kappa are positive (cubicle.g2o has 5021 such edges).
  bool isotropic_information = false;
};

// Reads a g2o file with VERTEX_SE3:QUAT, EDGE_SE3:QUAT and FIX lines into
// *graph (replaced; untouched on error). Blank lines and lines starting with
// '#' are skipped; any other tag is an error, as are missing or extra
// fields, numbers that do not parse or are not finite, quaternions whose
// norm is not within 1e-3 of 1 (those within are normalised), information
// matrices that are not positive definite, an edge from a vertex to itself,
// duplicate vertex ids, and edges or FIX lines that name a vertex no
// VERTEX_SE3:QUAT line defines. The information is given as its upper
// triangle, row by row (21 numbers), and mirrored.
Status ReadG2oPoseGraph(const std::string& path,
                        PoseGraph* graph,
                        const G2oReadOptions& options = G2oReadOptions());

struct PoseGraphSolveOptions {
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
  double initial_cost = 0.0;  // 1/2 sum of r^T r, as Ceres reports it
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
// Cholesky), one PoseGraphEdgeFactor per edge. Gauge: the vertices in
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

// The poses as (timestamp, T_w,id) with the vertex id as the timestamp, in
// increasing id order.
std::vector<std::pair<double, Rigid3d>> PoseGraphTrajectory(
    const PoseGraph& graph);

}  // namespace symba

#endif  // SYMBA_IO_POSE_GRAPH_H_
