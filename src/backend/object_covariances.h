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
#include "symba/backend/object_covariance.h"
#include "symba/common/status.h"

namespace symba::internal {

// Fails only if Ceres cannot compute the solve's covariance (a
// rank-deficient problem); an object that neither source covers is left
// out.
Status ObjectCovariances(const ObjectList& objects,
                         FactorGraph* graph,
                         std::vector<MapObjectCovariance>* covariances);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_OBJECT_COVARIANCES_H_
