// Marginalisation: factors that leave the problem for good are linearised
// at the current estimate, the blocks only they constrain are eliminated by
// the Schur complement, and what they said about the remaining blocks is
// returned as one MarginalPriorFactor (symba/factors/marginal_prior_factor.h;
// docs/backend.md "The window"). Not installed.
//
// How each factor is linearised:
//   - at the current value of every block, with the residual's Jacobian
//     mapped into each block's tangent space by its manifold's PlusJacobian;
//   - a robust loss by its first- and second-order correction (Triggs et
//     al., "Bundle adjustment, a modern synthesis", Sec. 4.3):
//       s = |r|^2, alpha = 1 - sqrt(1 + 2 s rho''/rho') (0 if rho'' <= 0),
//       r <- sqrt(rho') / (1 - alpha) r,
//       J <- sqrt(rho') (I - alpha r r^T / s) J
//     so that J^T J and J^T r are the loss's Gauss-Newton terms;
//   - a max-mixture by its current winner, but only if the winner leads
//     every rival by min_winner_margin in cost (negative log-likelihood)
//     and is not the null hypothesis; otherwise the factor is dropped: an
//     ambiguous mode must not be frozen into the prior. A rival is a
//     component whose whitened residual differs from the winner's by more
//     than rival_distance (components of one mode are no rivals);
//   - a factor whose evaluation fails or is not finite is dropped.
// Constant blocks take no part (their value is used, they get no columns).
// Safeguards: H_mm is inverted through its eigenvalues, those at most
// eigenvalue_threshold times the largest being treated as zero; the prior's
// information H* is symmetrised and factored the same way, so it is
// symmetric positive semi-definite by construction; kept blocks about which
// nothing is known (all-zero columns) leave the prior.
#ifndef SYMBA_SRC_BACKEND_MARGINALIZATION_H_
#define SYMBA_SRC_BACKEND_MARGINALIZATION_H_

#include <functional>
#include <memory>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include "symba/common/status.h"
#include "symba/factors/marginal_prior_factor.h"

namespace symba::internal {

struct MarginalizationOptions {
  double min_winner_margin = 2.0;       // cost units (nats)
  double rival_distance = 5.0;          // whitened residual units
  double eigenvalue_threshold = 1e-10;  // relative to the largest eigenvalue
};

// A factor to marginalise (borrowed; blocks in the cost function's order).
struct MarginalizationTerm {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;
  std::vector<double*> blocks;
  // Its information is scaled by this (> 0): a term split between two
  // conditionals enters each with a share.
  double weight = 1.0;
};

enum class BlockRole { kKeep, kEliminate, kConstant };

struct BlockDescription {
  BlockRole role = BlockRole::kKeep;
  // Its manifold (null: Euclidean). Must be ceres::EigenQuaternionManifold,
  // symba::AxisManifold or null: the prior measures in those tangents.
  const ceres::Manifold* manifold = nullptr;
};

struct MarginalizationResult {
  std::unique_ptr<MarginalPriorFactor> prior;  // null: nothing to keep
  std::vector<double*> blocks;                 // the prior's blocks
  int linearized = 0;                          // terms that entered the prior
  int ambiguous = 0;  // max-mixtures dropped (margin or null hypothesis)
  int failed = 0;     // terms dropped because they could not be evaluated
};

using BlockDescriber = std::function<BlockDescription(const double* block)>;

// Fails only on a block whose manifold the prior cannot express.
Status Marginalize(const std::vector<MarginalizationTerm>& terms,
                   const BlockDescriber& describe,
                   const MarginalizationOptions& options,
                   MarginalizationResult* result);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_MARGINALIZATION_H_
