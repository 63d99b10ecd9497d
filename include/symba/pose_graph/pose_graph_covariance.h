// Marginal covariances of a 3-D pose graph's vertices (docs/pose-graphs.md
// "Covariances"): the inverse of the graph's Gauss-Newton information at its
// poses, with the gauge held, in world-frame coordinates (GTSAM's
// marginalCovariance gives the same marginal in the vertex's own frame,
// rotation first); or, where the edges' noise is said to differ from their
// information by factors, the covariance of the poses that information
// makes of that noise.
#ifndef SYMBA_POSE_GRAPH_POSE_GRAPH_COVARIANCE_H_
#define SYMBA_POSE_GRAPH_POSE_GRAPH_COVARIANCE_H_

#include <cstdint>
#include <set>
#include <vector>

#include "symba/common/status.h"
#include "symba/factors/pose_component.h"
#include "symba/factors/pose_graph_edge.h"
#include "symba/pose_graph/pose_graph.h"

namespace symba {

// How much larger (or smaller) an edge's noise is than its information
// says, as variance factors of its whitened residual's rows: the first
// three (the translation, for an information without translation-rotation
// coupling) and the last three.
struct EdgeNoiseFactors {
  double translation = 1.0;
  double rotation = 1.0;
};

struct PoseGraphCovarianceOptions {
  PoseGraphRotationError rotation_error = PoseGraphRotationError::kRadians;
  // Vertices whose rotation is taken as known (held at its value): a
  // vertex that only position measurements reach (its edges' rotation
  // information negligible) would otherwise leave the information matrix
  // nearly singular. Their covariances are conditioned on that rotation;
  // its rows and columns are zero.
  std::set<int64_t> rotation_held;
  int num_threads = 1;
  // Empty: the covariance is the inverse of the information, H^-1. Else one
  // entry per edge (graph order): each edge's noise is its information's
  // times these factors (F, per whitened row), and the covariance is that
  // of the poses the stated information makes of such noise (the
  // "sandwich" of an estimator weighed other than its noise):
  //   H^-1 (J^T F J) H^-1,  H = J^T J,
  // J the whitened Jacobian at the graph's poses. With every factor c it is
  // c H^-1. This route factors H with Eigen's sparse LDL^T, single-threaded
  // (num_threads is not used).
  std::vector<EdgeNoiseFactors> noise_factors;
};

// The marginal covariance of each of `vertices` at the graph's poses (the
// graph is not optimised: solve it first), 6 x 6 in the order
// [translation t_w (world frame, m); w (rad)], w the world-frame rotation
// vector of R_w <- Exp(w) R_w; positive semi-definite. The gauge is
// OptimizePoseGraph's (the fixed vertices, else the smallest id of each
// connected component): its vertices' covariances are zero, the others'
// are relative to it.
//
// Errors (nothing written): the graph is invalid (as for OptimizePoseGraph),
// a requested vertex has no edge, the information is rank deficient (a
// vertex not determined by its edges), or noise_factors is given with
// another size than the edges' or a factor that is not finite and positive.
Status PoseGraphCovariances(const PoseGraph& graph,
                            const std::vector<int64_t>& vertices,
                            const PoseGraphCovarianceOptions& options,
                            std::vector<Matrix6d>* covariances);

}  // namespace symba

#endif  // SYMBA_POSE_GRAPH_POSE_GRAPH_COVARIANCE_H_
