// 3-D pose graphs in the g2o text format (docs/pose-graphs.md): reading. The
// graph is optimised by symba/pose_graph/optimize_pose_graph.h and its poses
// written as a TUM trajectory by symba/io/tum_trajectory.h:
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

#include <string>

#include "symba/common/status.h"
#include "symba/pose_graph/pose_graph.h"

namespace symba {

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

}  // namespace symba

#endif  // SYMBA_IO_POSE_GRAPH_H_
