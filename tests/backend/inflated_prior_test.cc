// A prior made less certain about its mean (symba/factors/inflated_prior.h):
// its information becomes (L^-1 + D)^-1, exactly where L is invertible and
// per eigen-direction where it is not (the unconstrained directions stay
// unconstrained); its minimum stays where it was, with the same cost; no
// added variance leaves it as it was; bad variances are refused.
#include "symba/factors/inflated_prior.h"

#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "test_support/random.h"

namespace symba {
namespace {

using symba::testing::TestRandom;

// A prior on one 3-vector block at x0 with the rows A and offset e.
std::unique_ptr<MarginalPriorFactor> PointPrior(const Eigen::Vector3d& x0,
                                                const Eigen::MatrixXd& A,
                                                const Eigen::VectorXd& e) {
  std::unique_ptr<MarginalPriorFactor> prior;
  EXPECT_TRUE(MarginalPriorFactor::Create(
                  {{PriorBlockKind::kEuclidean, x0}}, A, e, &prior)
                  .ok());
  return prior;
}

double Cost(const MarginalPriorFactor& prior, const Eigen::Vector3d& x) {
  const double* parameters[1] = {x.data()};
  Eigen::VectorXd r(prior.A().rows());
  EXPECT_TRUE(prior.Evaluate(parameters, r.data(), nullptr));
  return 0.5 * r.squaredNorm();
}

Eigen::Matrix3d Information(const MarginalPriorFactor& prior) {
  return prior.Information();
}

TEST(InflatePrior, AddsTheVarianceToAFullRankPriorsCovariance) {
  TestRandom random(3);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d x0 = random.NormalVector(2.0);
    // Four rows, so that the prior has a cost at its minimum.
    Eigen::MatrixXd A(4, 3);
    for (int i = 0; i < 4; ++i) A.row(i) = 5.0 * random.NormalVector(1.0);
    Eigen::VectorXd e(4);
    for (int i = 0; i < 4; ++i) e(i) = random.Uniform(-2.0, 2.0);
    const auto prior = PointPrior(x0, A, e);
    const Eigen::Vector3d variance(0.01, 0.04, 0.09);

    std::unique_ptr<MarginalPriorFactor> inflated;
    ASSERT_TRUE(InflatePrior(*prior, variance, &inflated).ok());

    const Eigen::Matrix3d L = A.transpose() * A;
    const Eigen::Matrix3d expected =
        (L.inverse() + Eigen::Matrix3d(variance.asDiagonal())).inverse();
    EXPECT_LT((Information(*inflated) - expected).norm(),
              1e-9 * expected.norm());
    // The same minimum, with the same cost there.
    const Eigen::Vector3d mean = x0 + A.colPivHouseholderQr().solve(-e);
    EXPECT_NEAR(Cost(*inflated, mean), Cost(*prior, mean), 1e-9);
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d step = 1e-3 * Eigen::Vector3d::Unit(axis);
      EXPECT_GT(Cost(*inflated, mean + step), Cost(*inflated, mean));
      EXPECT_GT(Cost(*inflated, mean - step), Cost(*inflated, mean));
    }
    // Less certain, not more: the information fell in every direction.
    const Eigen::Matrix3d lost = L - Information(*inflated);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(lost)
                  .eigenvalues()
                  .minCoeff(),
              0.0);
  }
}

TEST(InflatePrior, LeavesADirectionThePriorDidNotConstrainFree) {
  // Information 4 along x, 1 along y, none along z.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 3);
  A(0, 0) = 2.0;
  A(1, 1) = 1.0;
  const Eigen::Vector2d e(0.4, -0.3);
  const Eigen::Vector3d x0(1.0, 2.0, 3.0);
  const auto prior = PointPrior(x0, A, e);

  std::unique_ptr<MarginalPriorFactor> inflated;
  ASSERT_TRUE(
      InflatePrior(*prior, Eigen::Vector3d::Constant(0.25), &inflated).ok());

  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
  expected(0, 0) = 4.0 / (1.0 + 0.25 * 4.0);
  expected(1, 1) = 1.0 / (1.0 + 0.25 * 1.0);
  EXPECT_LT((Information(*inflated) - expected).norm(), 1e-12);
  // The minimum (x0 + (-0.2, 0.3, anything)) keeps its cost of zero.
  const Eigen::Vector3d mean = x0 + Eigen::Vector3d(-0.2, 0.3, 7.0);
  EXPECT_NEAR(Cost(*inflated, mean), 0.0, 1e-24);
  EXPECT_NEAR(Cost(*inflated, mean + Eigen::Vector3d(0.1, 0.0, 0.0)),
              0.5 * expected(0, 0) * 0.01,
              1e-12);
}

// Turned, with an information of 1e8: the unconstrained direction gains
// nothing (no rounding of A^T A leaks into it).
TEST(InflatePrior, KeepsATurnedUnconstrainedDirectionFreeAtHighInformation) {
  TestRandom random(17);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Matrix3d R = random.Rotation().toRotationMatrix();
    Eigen::MatrixXd A(2, 3);
    A.row(0) = 1e4 * R.col(0).transpose();
    A.row(1) = 1e3 * R.col(1).transpose();
    const auto prior =
        PointPrior(random.NormalVector(1.0), A, Eigen::Vector2d(3.0, -2.0));
    std::unique_ptr<MarginalPriorFactor> inflated;
    ASSERT_TRUE(
        InflatePrior(*prior, Eigen::Vector3d::Constant(0.01), &inflated).ok());
    const Eigen::Matrix3d L = Information(*inflated);
    // Forming A^T A first left about 1e-8 here.
    EXPECT_LT((inflated->A() * R.col(2)).squaredNorm(), 1e-20);
    EXPECT_NEAR(R.col(0).dot(L * R.col(0)), 1e8 / (1.0 + 1e8 * 0.01), 1e-6);
    EXPECT_NEAR(R.col(1).dot(L * R.col(1)), 1e6 / (1.0 + 1e6 * 0.01), 1e-6);
  }
}

// Two inflations add their variances, and the rows do not grow.
TEST(InflatePrior, InflatingTwiceAddsTheVariances) {
  TestRandom random(23);
  Eigen::MatrixXd A(5, 3);
  for (int i = 0; i < 5; ++i) A.row(i) = 4.0 * random.NormalVector(1.0);
  Eigen::VectorXd e(5);
  for (int i = 0; i < 5; ++i) e(i) = random.Uniform(-1.0, 1.0);
  const auto prior = PointPrior(random.NormalVector(1.0), A, e);
  const Eigen::Vector3d first(0.01, 0.02, 0.03);
  const Eigen::Vector3d second(0.04, 0.0, 0.01);
  std::unique_ptr<MarginalPriorFactor> once;
  std::unique_ptr<MarginalPriorFactor> twice;
  ASSERT_TRUE(InflatePrior(*prior, first, &once).ok());
  ASSERT_TRUE(InflatePrior(*once, second, &twice).ok());
  const Eigen::Matrix3d L = A.transpose() * A;
  const Eigen::Matrix3d expected =
      (L.inverse() + Eigen::Matrix3d((first + second).asDiagonal())).inverse();
  EXPECT_LT((Information(*twice) - expected).norm(), 1e-9 * expected.norm());
  EXPECT_EQ(twice->A().rows(), once->A().rows());
  EXPECT_LE(once->A().rows(), 4);
}

TEST(InflatePrior, WithoutAddedVarianceSaysWhatThePriorSaid) {
  TestRandom random(5);
  Eigen::MatrixXd A(3, 3);
  for (int i = 0; i < 3; ++i) A.row(i) = random.NormalVector(3.0);
  const Eigen::Vector3d e = random.NormalVector(1.0);
  const Eigen::Vector3d x0 = random.NormalVector(1.0);
  const auto prior = PointPrior(x0, A, e);
  std::unique_ptr<MarginalPriorFactor> same;
  ASSERT_TRUE(InflatePrior(*prior, Eigen::Vector3d::Zero(), &same).ok());
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d x = x0 + random.NormalVector(0.5);
    EXPECT_NEAR(
        Cost(*same, x), Cost(*prior, x), 1e-9 * (1.0 + Cost(*prior, x)));
  }
}

TEST(InflatePrior, RefusesAVarianceOfTheWrongSizeNegativeOrNotFinite) {
  const auto prior = PointPrior(Eigen::Vector3d::Zero(),
                                Eigen::MatrixXd::Identity(3, 3),
                                Eigen::VectorXd::Zero(3));
  std::unique_ptr<MarginalPriorFactor> out;
  EXPECT_FALSE(InflatePrior(*prior, Eigen::Vector2d(1.0, 1.0), &out).ok());
  EXPECT_FALSE(
      InflatePrior(*prior, Eigen::Vector3d(1.0, -1.0, 1.0), &out).ok());
  EXPECT_FALSE(
      InflatePrior(*prior, Eigen::Vector3d(1.0, std::nan(""), 1.0), &out).ok());
  EXPECT_EQ(out, nullptr);
}

}  // namespace
}  // namespace symba
