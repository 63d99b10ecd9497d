// MarginalPriorFactor: the linear prior that marginalisation leaves on the
// blocks still connected to what was eliminated (docs/backend.md "The
// window": marginalisation).
//
// Marginalising blocks m out of a linearised problem with Hessian H and
// gradient g (in the blocks' tangent spaces, at the estimate x0) leaves,
// by the Schur complement,
//
//   H* = H_kk - H_km H_mm^+ H_mk,   g* = g_k - H_km H_mm^+ g_m
//
// on the kept blocks k. With H* = U L U^T (eigenvalues above a threshold
// only) the factor's residual is
//
//   r(x) = A d(x) + e,   A = L^(1/2) U^T,   e = L^(-1/2) U^T g*
//   d(x) = [Minus(x_1, x0_1); ...; Minus(x_n, x0_n)]   (tangent, stacked)
//
// so that 0.5 |r|^2 = const + g*^T d + 0.5 d^T H* d: the quadratic the
// eliminated factors contributed. A and e are frozen at x0 (the first
// estimate); the Jacobian is exact at every x:
//
//   dr/dx_b = A_b dMinus(x_b, x0_b)/dx_b          (rows x ambient size)
//
// The tangent difference Minus of each block is that of its manifold in
// the problem:
//   kEuclidean   y - x0
//   kQuaternion  Log(y x0^-1) with Log(q) = atan2(|v|, w) v / |v|: Ceres's
//                EigenQuaternionManifold (Eigen order [x, y, z, w]; tangent
//                units are half-angles, Plus(x, d) = Exp(d) x)
//   kUnitAxis    symba's AxisManifold: B(x0)^T y scaled to the geodesic
//                angle atan2(|B^T y|, x0 . y) (tangent units are radians)
// Minus is undefined at the antipode of x0 (a rotation of 360 degrees, an
// axis turned by 180); Evaluate returns false there.
#ifndef SYMBA_FACTORS_MARGINAL_PRIOR_FACTOR_H_
#define SYMBA_FACTORS_MARGINAL_PRIOR_FACTOR_H_

#include <memory>
#include <vector>

#include <ceres/cost_function.h>
#include <Eigen/Core>

#include "symba/common/status.h"

namespace symba {

enum class PriorBlockKind { kEuclidean, kQuaternion, kUnitAxis };

// A block of the prior: its kind, its ambient size (a kEuclidean block has
// any size >= 1; kQuaternion 4, kUnitAxis 3) and its value x0 at
// linearisation.
struct PriorBlock {
  PriorBlockKind kind = PriorBlockKind::kEuclidean;
  Eigen::VectorXd x0;
};

int PriorBlockTangentSize(const PriorBlock& block);

// The tangent difference d = Minus(y, x0) of a block of `kind` (tangent size
// t, ambient size n) and, if `jacobian` is not null, dd/dy (t x n, row
// major). False at the antipode of x0 (see above) or for non-finite input.
bool PriorTangentDifference(PriorBlockKind kind,
                            int ambient_size,
                            const double* y,
                            const double* x0,
                            double* delta,
                            double* jacobian);

class MarginalPriorFactor final : public ceres::CostFunction {
 public:
  // A: rows x (sum of the blocks' tangent sizes); e: rows. Checks sizes,
  // finiteness and unit norms of the quaternion and axis blocks.
  static Status Create(std::vector<PriorBlock> blocks,
                       Eigen::MatrixXd A,
                       Eigen::VectorXd e,
                       std::unique_ptr<MarginalPriorFactor>* factor);

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override;

  const std::vector<PriorBlock>& blocks() const { return blocks_; }
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::VectorXd& e() const { return e_; }
  // A^T A: the information the prior holds (tangent, at x0).
  Eigen::MatrixXd Information() const { return A_.transpose() * A_; }

 private:
  MarginalPriorFactor(std::vector<PriorBlock> blocks,
                      Eigen::MatrixXd A,
                      Eigen::VectorXd e);

  std::vector<PriorBlock> blocks_;
  std::vector<int> tangent_offsets_;
  Eigen::MatrixXd A_;
  Eigen::VectorXd e_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_MARGINAL_PRIOR_FACTOR_H_
