// Each confirmed map object's covariance (symba/backend/object_covariance.h)
// at the current estimate: from the last solve's problem for an object it
// holds, jointly with everything it held free; else from the prior the
// object's marginalised observations left (its information A^T A, at the
// prior's linearisation point). The tangent of each block maps to what is
// reported:
//   t_wo   Euclidean: the position covariance as it is (m^2);
//   q_wo   Ceres' quaternion tangent d moves R by Exp(2 d) (half-angles):
//          rotation = 4 C_d (rad^2, world frame);
//   a_w    AxisManifold, Plus(a, d) with basis B(a) in radians:
//          axis = B C_d B^T (3x3, rank 2);
//   theta  Euclidean (rad^2).
// Not installed.
#ifndef SYMBA_SRC_BACKEND_OBJECT_COVARIANCES_H_
#define SYMBA_SRC_BACKEND_OBJECT_COVARIANCES_H_

#include <vector>

#include "backend/factor_graph.h"
#include "backend/keyframe_graph.h"
#include "symba/backend/object_covariance.h"
#include "symba/common/status.h"

namespace symba::internal {

// Fails only if Ceres cannot compute the solve's covariance (a
// rank-deficient problem); an object that neither source covers is left
// out.
Status ObjectCovariances(const ObjectList& objects,
                         FactorGraph* graph,
                         std::vector<MapObjectCovariance>* covariances);

// The same in the world frame, where the last solve held keyframes that
// left its window as known (docs/backend.md "Covariances"): an object that
// is a vertex of `graph` (MakeKeyframeGraph of `num_keyframes` keyframes
// and `objects`, keyframe 0 the gauge) gets that vertex's marginal
// covariance as its position, an asymmetric object (GraphObject::rotation)
// as its rotation, a symmetric one whose edges measure its axis
// (GraphObject::HasAxis) as its axis: axis = Hat(a_w) C_w Hat(a_w)^T for
// the world rotation vector's covariance C_w. Angle variances stay the
// solve's or the prior's. `covariances` (ObjectCovariances' reports) are
// replaced in the order of `states` by one report per confirmed object
// that either covers. `options`: PoseGraphCovariances' for that graph
// (KeyframeGraphCovarianceOptions, with or without noise factors). Fails
// (nothing changed) where the graph's information is rank deficient.
Status InWorldFrame(const PoseGraph& graph,
                    int num_keyframes,
                    const std::vector<GraphObject>& objects,
                    const ObjectList& states,
                    const PoseGraphCovarianceOptions& options,
                    std::vector<MapObjectCovariance>* covariances);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_OBJECT_COVARIANCES_H_
