// A marginalisation prior (marginal_prior_factor.h) made less certain by an
// added covariance, about the same mean: what a prior says after its
// entity was moved by a correction that is itself uncertain, as a loop
// closure moves a map point by the mean of its observers' moves
// (docs/loop-closure.md "Moving the past").
//
// With the prior's information L = A^T A (tangent, at x0) and its mean
// d* = argmin_d |A d + e| (the minimum-norm solution where L is singular),
// adding the covariance D (diagonal, >= 0, one entry per tangent
// dimension) gives
//
//   L' = L (I + D L)^-1      = (L^-1 + D)^-1 where L is invertible,
//
// which is symmetric and positive semi-definite with the null space of L
// (no direction the prior did not constrain gains information). It is
// computed without forming A^T A: with A = W S V^T and B = S_k V_k^T over
// the k directions whose information is above 1e-10 of the largest,
// L' = B^T (I_k + B D B^T)^-1 B, and with (I_k + B D B^T)^-1 = C C^T the
// inflated factor has A' = C^T B (k rows) and e' = -A' d*, plus one row
// that keeps the prior's cost at its mean, |A d* + e|, where that is not
// zero. So 0.5 |r'|^2 has its minimum where the prior's was, with the same
// value, and inflating again never adds rows.
#ifndef SYMBA_FACTORS_INFLATED_PRIOR_H_
#define SYMBA_FACTORS_INFLATED_PRIOR_H_

#include <memory>

#include <Eigen/Core>

#include "symba/common/status.h"
#include "symba/factors/marginal_prior_factor.h"

namespace symba {

// `added_variance`: one entry per tangent dimension of `prior`, in its
// order, each finite and >= 0. Otherwise an error, and *inflated is
// untouched.
Status InflatePrior(const MarginalPriorFactor& prior,
                    const Eigen::VectorXd& added_variance,
                    std::unique_ptr<MarginalPriorFactor>* inflated);

}  // namespace symba

#endif  // SYMBA_FACTORS_INFLATED_PRIOR_H_
