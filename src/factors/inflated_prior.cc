#include "symba/factors/inflated_prior.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/SVD>

namespace symba {
namespace {

// Directions whose information is below this share of the largest are
// taken as unconstrained (as marginalisation does).
constexpr double kRelativeInformationThreshold = 1e-10;

}  // namespace

Status InflatePrior(const MarginalPriorFactor& prior,
                    const Eigen::VectorXd& added_variance,
                    std::unique_ptr<MarginalPriorFactor>* inflated) {
  const Eigen::MatrixXd& A = prior.A();
  const Eigen::VectorXd& e = prior.e();
  const int n = static_cast<int>(A.cols());
  if (added_variance.size() != n) {
    return Status::Error(
        "the added variance needs one entry per tangent "
        "dimension of the prior");
  }
  if (!added_variance.allFinite() || (added_variance.array() < 0.0).any()) {
    return Status::Error("the added variance must be finite and >= 0");
  }
  // A = W S V^T: the information L = A^T A = B^T B with B = S_k V_k^T over
  // the directions it constrains (k of them), without forming A^T A.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(
      A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double largest = s.size() > 0 ? s(0) : 0.0;
  int k = 0;
  while (k < s.size() &&
         s(k) * s(k) > kRelativeInformationThreshold * largest * largest) {
    ++k;
  }
  // The prior's mean (minimum norm in the unconstrained directions) and its
  // cost there.
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < k; ++i) {
    mean -= svd.matrixV().col(i) * (svd.matrixU().col(i).dot(e) / s(i));
  }
  const double floor = (A * mean + e).norm();
  // L' = L (I + D L)^-1 = B^T (I_k + B D B^T)^-1 B (push-through), so with
  // (I_k + B D B^T)^-1 = C C^T the rows A' = C^T B span only what L did.
  const Eigen::MatrixXd B =
      s.head(k).asDiagonal() * svd.matrixV().leftCols(k).transpose();
  const Eigen::MatrixXd M = (Eigen::MatrixXd::Identity(k, k) +
                             B * added_variance.asDiagonal() * B.transpose())
                                .inverse();
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (M + M.transpose()));
  // The cost at the mean needs a row of its own only where it is not zero
  // (a prior from marginalisation has none).
  const bool floor_row = floor > 1e-12 * std::max(1.0, e.norm());
  const int rows = std::max(1, k + (floor_row ? 1 : 0));
  Eigen::MatrixXd A_new = Eigen::MatrixXd::Zero(rows, n);
  Eigen::VectorXd e_new = Eigen::VectorXd::Zero(rows);
  if (k > 0) {
    A_new.topRows(k) = llt.matrixU() * B;
    e_new.head(k) = -A_new.topRows(k) * mean;
  }
  if (floor_row) e_new(rows - 1) = floor;
  return MarginalPriorFactor::Create(
      prior.blocks(), std::move(A_new), std::move(e_new), inflated);
}

}  // namespace symba
