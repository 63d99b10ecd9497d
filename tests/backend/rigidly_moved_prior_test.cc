// A prior moved with its blocks (symba/factors/rigidly_moved_prior.h): at
// the moved values it gives exactly the residual the original gave, for
// quaternion, position, unit-axis and unmoved blocks each moved by a
// different rigid transform, far from x0 too; x0 itself moves; a role that
// does not fit its block is refused.
#include "symba/factors/rigidly_moved_prior.h"

#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "test_support/random.h"

namespace symba {
namespace {

using symba::testing::TestRandom;

Rigid3d RandomMotion(TestRandom* random) {
  return Rigid3d(random->Rotation(), random->NormalVector(3.0));
}

// Blocks [q (quaternion), t (position), a (axis), theta (unmoved)].
struct Values {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
  Eigen::Vector3d a;
  double theta = 0.0;
};

Values Moved(const Values& v, const std::vector<RigidBlockMotion>& motions) {
  Values moved = v;
  moved.q = (motions[0].W.q * v.q).normalized();
  moved.t = motions[1].W * v.t;
  moved.a = (motions[2].W.q * v.a).normalized();
  return moved;
}

Eigen::VectorXd Residual(const MarginalPriorFactor& prior, const Values& v) {
  const double theta[1] = {v.theta};
  const double* parameters[4] = {
      v.q.coeffs().data(), v.t.data(), v.a.data(), theta};
  Eigen::VectorXd r(prior.A().rows());
  EXPECT_TRUE(prior.Evaluate(parameters, r.data(), nullptr));
  return r;
}

TEST(MovePriorRigidly, GivesTheSameResidualAtTheMovedValues) {
  TestRandom random(11);
  for (int trial = 0; trial < 20; ++trial) {
    Values x0{random.Rotation(),
              random.NormalVector(2.0),
              random.UnitVector(),
              random.Uniform(-3, 3)};
    std::vector<PriorBlock> blocks(4);
    blocks[0] = {PriorBlockKind::kQuaternion, x0.q.coeffs()};
    blocks[1] = {PriorBlockKind::kEuclidean, x0.t};
    blocks[2] = {PriorBlockKind::kUnitAxis, x0.a};
    blocks[3] = {PriorBlockKind::kEuclidean,
                 Eigen::VectorXd::Constant(1, x0.theta)};
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(9, 9);
    const Eigen::VectorXd e = Eigen::VectorXd::Random(9);
    std::unique_ptr<MarginalPriorFactor> prior;
    ASSERT_TRUE(MarginalPriorFactor::Create(blocks, A, e, &prior).ok());

    const std::vector<RigidBlockMotion> motions = {
        {RigidBlockRole::kRotation, RandomMotion(&random)},
        {RigidBlockRole::kPosition, RandomMotion(&random)},
        {RigidBlockRole::kAxis, RandomMotion(&random)},
        {RigidBlockRole::kUnmoved, RandomMotion(&random)}};
    std::unique_ptr<MarginalPriorFactor> moved;
    const Status status = MovePriorRigidly(*prior, motions, &moved);
    ASSERT_TRUE(status.ok()) << status.message();

    // x0 moved; e kept.
    const Values x0_moved = Moved(x0, motions);
    EXPECT_LT((moved->blocks()[1].x0 - x0_moved.t).norm(), 1e-12);
    EXPECT_LT((moved->blocks()[2].x0 - x0_moved.a).norm(), 1e-12);
    EXPECT_LT(Eigen::Quaterniond(Eigen::Vector4d(moved->blocks()[0].x0))
                  .angularDistance(x0_moved.q),
              1e-12);
    EXPECT_EQ(moved->blocks()[3].x0(0), x0.theta);
    EXPECT_EQ(moved->e(), prior->e());

    // The same residual near and far from x0 (up to 2.5 rad, 2 m).
    for (double spread : {0.01, 0.3, 1.0}) {
      const Values y{(random.RotationOfAngle(2.5 * spread) * x0.q).normalized(),
                     x0.t + random.NormalVector(2.0 * spread),
                     (x0.a + random.NormalVector(spread)).normalized(),
                     x0.theta + random.Uniform(-spread, spread)};
      const Eigen::VectorXd r = Residual(*prior, y);
      const Eigen::VectorXd r_moved = Residual(*moved, Moved(y, motions));
      EXPECT_LT((r - r_moved).norm(), 1e-9 * (1.0 + r.norm()))
          << "trial " << trial << ", spread " << spread;
    }
  }
}

TEST(MovePriorRigidly, RefusesARoleThatDoesNotFitItsBlock) {
  std::vector<PriorBlock> blocks = {
      {PriorBlockKind::kEuclidean, Eigen::VectorXd::Zero(1)},
      {PriorBlockKind::kQuaternion, Eigen::Vector4d(0, 0, 0, 1)}};
  std::unique_ptr<MarginalPriorFactor> prior;
  ASSERT_TRUE(MarginalPriorFactor::Create(blocks,
                                          Eigen::MatrixXd::Identity(4, 4),
                                          Eigen::VectorXd::Zero(4),
                                          &prior)
                  .ok());
  std::unique_ptr<MarginalPriorFactor> moved;
  // A 1-vector is no position; a quaternion is no axis.
  EXPECT_FALSE(MovePriorRigidly(*prior,
                                {{RigidBlockRole::kPosition, Rigid3d()},
                                 {RigidBlockRole::kRotation, Rigid3d()}},
                                &moved)
                   .ok());
  EXPECT_FALSE(MovePriorRigidly(*prior,
                                {{RigidBlockRole::kUnmoved, Rigid3d()},
                                 {RigidBlockRole::kAxis, Rigid3d()}},
                                &moved)
                   .ok());
  EXPECT_FALSE(
      MovePriorRigidly(*prior, {{RigidBlockRole::kUnmoved, Rigid3d()}}, &moved)
          .ok());
  EXPECT_EQ(moved, nullptr);
}

}  // namespace
}  // namespace symba
