#include "symba/factors/inflated_prior.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

namespace symba {

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
  // The prior's mean and its cost there.
  const Eigen::VectorXd mean = A.completeOrthogonalDecomposition().solve(-e);
  const double floor = (A * mean + e).norm();
  const Eigen::MatrixXd L = A.transpose() * A;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd inflated_L =
      L * (I + added_variance.asDiagonal() * L).inverse();
  inflated_L = 0.5 * (inflated_L + inflated_L.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(inflated_L);
  const Eigen::VectorXd& s = eigen.eigenvalues();
  const double threshold = 1e-12 * std::max(1.0, s.maxCoeff());
  std::vector<int> kept;
  for (int i = 0; i < n; ++i) {
    if (s(i) > threshold) kept.push_back(i);
  }
  const int rows = static_cast<int>(kept.size());
  Eigen::MatrixXd A_new = Eigen::MatrixXd::Zero(rows + 1, n);
  for (int r = 0; r < rows; ++r) {
    A_new.row(r) =
        std::sqrt(s(kept[r])) * eigen.eigenvectors().col(kept[r]).transpose();
  }
  Eigen::VectorXd e_new(rows + 1);
  e_new.head(rows) = -A_new.topRows(rows) * mean;
  e_new(rows) = floor;
  return MarginalPriorFactor::Create(
      prior.blocks(), std::move(A_new), std::move(e_new), inflated);
}

}  // namespace symba
