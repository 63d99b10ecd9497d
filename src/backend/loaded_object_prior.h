// The prior a map object loaded from a saved map keeps (docs/map-format.md
// "Loading"): its saved covariance, block-diagonal over its parameter
// groups, as a MarginalPriorFactor at the loaded estimate:
//
//   r = U d,   U^T U = blockdiag(P^-1, (R / 4)^-1 or C^-1, v_i^-1 ...)
//   d = [t - t0; Minus(q, q0); Minus(a_w, a_w0); theta_i - theta_i0 ...]
//
// P the position covariance (m^2); R the rotation covariance of an
// asymmetric object (rad^2, world rotation vector; the quaternion
// manifold's tangent is half the angle, hence R / 4); C = B^T S B the
// symmetric axis covariance S in the axis manifold's tangent basis B(a_w0);
// v_i a discrete angle's variance. A group whose covariance is not positive
// definite (or absent) gets no prior. Not installed.
#ifndef SYMBA_SRC_BACKEND_LOADED_OBJECT_PRIOR_H_
#define SYMBA_SRC_BACKEND_LOADED_OBJECT_PRIOR_H_

#include "backend/backend_state.h"
#include "symba/backend/object_covariance.h"

namespace symba::internal {

// The factor's record for `object` (index `o`) from `covariance`; false
// when no group has a positive definite covariance (no prior).
bool MakeLoadedObjectPrior(int o,
                           ObjectState* object,
                           const MapObjectCovariance& covariance,
                           FactorRecord* record);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_LOADED_OBJECT_PRIOR_H_
