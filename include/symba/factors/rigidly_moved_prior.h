// A marginalisation prior (marginal_prior_factor.h) carried along when the
// entities it constrains are moved rigidly, as a loop closure moves the
// past (docs/loop-closure.md "Moving the past").
//
// Each block b is moved by a rigid transform W_b = (R_b, p_b) according to
// what it is:
//
//   position    x -> R x + p     (a keyframe's t_wc, an object's t_wo, p_w)
//   rotation    q -> R q         (q_wc, an asymmetric object's q_wo)
//   axis        a -> R a         (a symmetric object's world axis)
//   unmoved     x -> x           (a discrete angle: measured from an anchor
//                                 that is moved with the object)
//
// The tangent difference of each block then turns by a fixed orthogonal
// map J_b, exactly at every y, not only near x0:
//
//   position, rotation   Minus(W y, W x0) = R Minus(y, x0)     J = R
//   axis                 J = B(R a0)^T R B(a0)  (2 x 2; B the axis
//                        manifold's tangent basis, geometry/tangent_basis.h)
//
// so the moved prior, with x0' = W x0, A' = A blockdiag(J_b^T), e' = e,
// gives at W y exactly the residual the prior gave at y: it says the same
// about the moved entities, at their new place.
#ifndef SYMBA_FACTORS_RIGIDLY_MOVED_PRIOR_H_
#define SYMBA_FACTORS_RIGIDLY_MOVED_PRIOR_H_

#include <memory>
#include <vector>

#include "symba/common/status.h"
#include "symba/factors/marginal_prior_factor.h"
#include "symba/geometry/rigid3.h"

namespace symba {

enum class RigidBlockRole { kUnmoved, kPosition, kRotation, kAxis };

struct RigidBlockMotion {
  RigidBlockRole role = RigidBlockRole::kUnmoved;
  Rigid3d W;  // the block's motion (identity: none)
};

// `motions` has one entry per block of `prior`, in its order. A position
// must be a 3-vector Euclidean block, a rotation a quaternion block, an
// axis a unit-axis block; otherwise an error, and *moved is untouched.
Status MovePriorRigidly(const MarginalPriorFactor& prior,
                        const std::vector<RigidBlockMotion>& motions,
                        std::unique_ptr<MarginalPriorFactor>* moved);

}  // namespace symba

#endif  // SYMBA_FACTORS_RIGIDLY_MOVED_PRIOR_H_
