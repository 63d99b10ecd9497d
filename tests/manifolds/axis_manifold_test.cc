#include "symba/manifolds/axis_manifold.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold_test_utils.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/geometry/angle.h"
#include "symba/geometry/sphere_log.h"
#include "symba/geometry/tangent_basis.h"
#include "test_support/random.h"

namespace symba {
namespace {

using PlusJacobianMatrix = Eigen::Matrix<double, 3, 2, Eigen::RowMajor>;
using MinusJacobianMatrix = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;

// Tolerance of Ceres's invariant matchers; the Jacobian checks compare with
// Ridders-extrapolated numeric derivatives, which are good to about 1e-10.
constexpr double kInvariantTolerance = 1e-9;

// The great-circle angle between two directions, accurate at every angle
// (acos loses half the digits near 0 and pi).
double AngleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// A tangent vector in a uniformly random direction with norm uniform in
// [0, max_norm).
Eigen::Vector2d RandomDelta(testing::TestRandom& random, double max_norm) {
  const double direction = random.Uniform(-kPi, kPi);
  const double norm = random.Uniform(0.0, max_norm);
  return norm * Eigen::Vector2d(std::cos(direction), std::sin(direction));
}

// A random unit vector at least ~25 degrees away from -x, so that Minus(y, x)
// is well conditioned.
Eigen::Vector3d RandomPointNotNearAntipode(testing::TestRandom& random,
                                           const Eigen::Vector3d& x) {
  Eigen::Vector3d y;
  do {
    y = random.UnitVector();
  } while (y.dot(x) < -0.9);
  return y;
}

// Runs Ceres's full set of manifold invariants at x: Plus(x, 0) = x,
// Minus(x, x) = 0, Minus(Plus(x, delta), x) = delta, Plus(x, Minus(y, x)) = y,
// Plus/Minus Jacobians against numeric differentiation, MinusJacobian *
// PlusJacobian = I and RightMultiplyByPlusJacobian.
void ExpectAxisManifoldInvariantsHold(const Eigen::Vector3d& x_in,
                                      const Eigen::Vector2d& delta_in,
                                      const Eigen::Vector3d& y_in) {
  using ceres::HasCorrectMinusJacobianAt;
  using ceres::HasCorrectPlusJacobianAt;
  using ceres::HasCorrectRightMultiplyByPlusJacobianAt;
  using ceres::MinusPlusIsIdentityAt;
  using ceres::MinusPlusJacobianIsIdentityAt;
  using ceres::PlusMinusIsIdentityAt;
  using ceres::Vector;
  using ceres::XMinusXIsZeroAt;
  using ceres::XPlusZeroIsXAt;
  const AxisManifold manifold;
  const Vector x = x_in;
  const Vector delta = delta_in;
  const Vector y = y_in;
  EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(
      manifold, x, delta, y, kInvariantTolerance);
}

// Unit vectors at and next to both poles and the equator: the places where a
// spherical-angle parameterisation or a branching basis could break.
std::vector<Eigen::Vector3d> SpecialPoints() {
  std::vector<Eigen::Vector3d> points = {
      Eigen::Vector3d(0.0, 0.0, 1.0),
      Eigen::Vector3d(0.0, 0.0, -1.0),
  };
  // Within 1e-12 of either pole, in several directions.
  for (const double z : {1.0, -1.0}) {
    for (const double angle : {0.0, 0.7, 2.0, -2.5}) {
      points.push_back(
          Eigen::Vector3d(1e-12 * std::cos(angle), 1e-12 * std::sin(angle), z)
              .normalized());
    }
    points.push_back(Eigen::Vector3d(1e-13, 0.0, z).normalized());
    points.push_back(Eigen::Vector3d(0.0, -1e-12, z).normalized());
  }
  // On the equator (z exactly 0, including -0.0) and just either side of it.
  for (const double angle : {0.0, 0.5 * kPi, 1.0, -2.0, kPi}) {
    for (const double z : {0.0, -0.0, 1e-12, -1e-12, 1e-300, -1e-300}) {
      Eigen::Vector3d p(std::cos(angle), std::sin(angle), 0.0);
      p.normalize();
      p.z() = z;  // |z| so small that the norm is still 1 to rounding.
      points.push_back(p);
    }
  }
  points.push_back(Eigen::Vector3d(1.0, 0.0, 0.0));
  points.push_back(Eigen::Vector3d(0.0, 1.0, 0.0));
  points.push_back(Eigen::Vector3d(-1.0, 0.0, 0.0));
  points.push_back(Eigen::Vector3d(0.0, -1.0, 0.0));
  return points;
}

std::string Describe(const Eigen::Vector3d& x) {
  Eigen::IOFormat format(
      Eigen::FullPrecision, Eigen::DontAlignCols, ", ", ", ", "", "", "[", "]");
  std::ostringstream out;
  out << x.transpose().format(format);
  return out.str();
}

TEST(AxisManifoldTest, SizesAreThreeAmbientTwoTangent) {
  const AxisManifold manifold;
  EXPECT_EQ(manifold.AmbientSize(), 3);
  EXPECT_EQ(manifold.TangentSize(), 2);
}

TEST(AxisManifoldTest, InvariantsHoldAtRandomPoints) {
  testing::TestRandom random(11);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d x = random.UnitVector();
    const Eigen::Vector2d delta = RandomDelta(random, kPi - 0.1);
    const Eigen::Vector3d y = RandomPointNotNearAntipode(random, x);
    SCOPED_TRACE("x = " + Describe(x));
    ExpectAxisManifoldInvariantsHold(x, delta, y);
  }
}

TEST(AxisManifoldTest, InvariantsHoldAtPolesAndEquator) {
  testing::TestRandom random(12);
  for (const Eigen::Vector3d& x : SpecialPoints()) {
    SCOPED_TRACE("x = " + Describe(x));
    // A few steps per point: short, long and along the basis directions.
    const std::vector<Eigen::Vector2d> deltas = {
        Eigen::Vector2d(1e-3, 0.0),
        Eigen::Vector2d(0.0, -0.5),
        Eigen::Vector2d(1.2, -2.0),
        Eigen::Vector2d(-(kPi - 0.1), 0.0),
        RandomDelta(random, kPi - 0.1),
    };
    for (const Eigen::Vector2d& delta : deltas) {
      ExpectAxisManifoldInvariantsHold(
          x, delta, RandomPointNotNearAntipode(random, x));
    }
    // y across the equator, and y next to the north pole (for x near the
    // south pole that is within ~1e-12 of -x, the hardest case for Minus).
    ExpectAxisManifoldInvariantsHold(
        x, deltas[2], Eigen::Vector3d(0.3, -0.2, -0.2).normalized());
    ExpectAxisManifoldInvariantsHold(
        x, deltas[2], Eigen::Vector3d(1e-12, 0.0, 1.0).normalized());
  }
}

TEST(AxisManifoldTest, TangentBasisIsOrthonormalRightHandedEverywhere) {
  testing::TestRandom random(13);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 1000; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    const Eigen::Matrix<double, 3, 2> basis = TangentBasis(x);
    ASSERT_TRUE(basis.allFinite());
    EXPECT_LT((basis.transpose() * basis - Eigen::Matrix2d::Identity())
                  .lpNorm<Eigen::Infinity>(),
              1e-15);
    EXPECT_LT((basis.transpose() * x).lpNorm<Eigen::Infinity>(), 1e-15);
    EXPECT_LT((basis.col(0).cross(basis.col(1)) - x).lpNorm<Eigen::Infinity>(),
              1e-15);
  }
}

TEST(AxisManifoldTest, PlusMovesByExactlyTheNormOfDelta) {
  const AxisManifold manifold;
  testing::TestRandom random(14);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 1000; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    for (const double norm : {1e-9, 1e-5, 0.3, 1.0, 2.5, kPi - 1e-3}) {
      const double direction = random.Uniform(-kPi, kPi);
      const Eigen::Vector2d delta =
          norm * Eigen::Vector2d(std::cos(direction), std::sin(direction));
      Eigen::Vector3d moved;
      ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), moved.data()));
      EXPECT_NEAR(AngleBetween(x, moved), norm, 1e-14 + 1e-14 * norm);
      // And with acos, the way the property is usually stated (acos cannot
      // resolve angles below sqrt(2 eps) ~ 2.1e-8, one ulp of cos below 1).
      EXPECT_NEAR(std::acos(std::clamp(x.dot(moved), -1.0, 1.0)), norm, 5e-8);
      // The direction of travel is B(x) delta. (Recovering it from `moved`
      // cancels digits when sin(norm) is small, hence the tolerance.)
      const Eigen::Vector3d expected_direction =
          (TangentBasis(x) * delta).normalized();
      const Eigen::Vector3d travel = (moved - x.dot(moved) * x).normalized();
      EXPECT_LT((travel - expected_direction).norm(), 1e-14 / std::sin(norm));
    }
  }
}

// Plus and Minus switch to series below a step of 1e-4 rad; both sides of the
// switch must round-trip to rounding error (a point 1e-12 rad from x is only
// resolved to about eps absolute, hence the absolute term).
TEST(AxisManifoldTest, SmallStepsRoundTripAcrossTheSeriesSwitch) {
  const AxisManifold manifold;
  testing::TestRandom random(20);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 200; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    for (const double norm :
         {1e-12, 1e-9, 1e-6, 5e-5, 9.99e-5, 1.001e-4, 2e-4, 1e-3}) {
      const double direction = random.Uniform(-kPi, kPi);
      const Eigen::Vector2d delta =
          norm * Eigen::Vector2d(std::cos(direction), std::sin(direction));
      Eigen::Vector3d moved;
      ASSERT_TRUE(manifold.Plus(x.data(), delta.data(), moved.data()));
      Eigen::Vector2d recovered;
      ASSERT_TRUE(manifold.Minus(moved.data(), x.data(), recovered.data()));
      EXPECT_LT((recovered - delta).norm(), 1e-15 + 1e-13 * norm)
          << "norm " << norm;
      EXPECT_NEAR(AngleBetween(x, moved), norm, 1e-15 + 1e-13 * norm);
    }
  }
}

// The reason symba does not reuse ceres::SphereManifold<3>: its tangent units
// are half-radians, so the same delta moves the point half as far.
TEST(AxisManifoldTest, SphereManifoldMovesHalfAsFar) {
  const AxisManifold axis_manifold;
  const ceres::SphereManifold<3> sphere_manifold;
  testing::TestRandom random(15);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d x = random.UnitVector();
    const Eigen::Vector2d delta =
        RandomDelta(random, 2.0) + Eigen::Vector2d(0.1, 0.0);  // never tiny
    Eigen::Vector3d ours;
    Eigen::Vector3d ceres_sphere;
    ASSERT_TRUE(axis_manifold.Plus(x.data(), delta.data(), ours.data()));
    ASSERT_TRUE(
        sphere_manifold.Plus(x.data(), delta.data(), ceres_sphere.data()));
    EXPECT_NEAR(AngleBetween(x, ours), delta.norm(), 1e-12);
    EXPECT_NEAR(AngleBetween(x, ceres_sphere), 0.5 * delta.norm(), 1e-12);

    // Minus inverts this: SphereManifold reports twice the angle.
    const Eigen::Vector3d y = RandomPointNotNearAntipode(random, x);
    Eigen::Vector2d ours_minus;
    Eigen::Vector2d ceres_minus;
    ASSERT_TRUE(axis_manifold.Minus(y.data(), x.data(), ours_minus.data()));
    ASSERT_TRUE(sphere_manifold.Minus(y.data(), x.data(), ceres_minus.data()));
    EXPECT_NEAR(ours_minus.norm(), AngleBetween(x, y), 1e-12);
    EXPECT_NEAR(ceres_minus.norm(), 2.0 * AngleBetween(x, y), 1e-12);
  }
  // A concrete number: a step of 1 rad from the north pole.
  const Eigen::Vector3d pole(0.0, 0.0, 1.0);
  const Eigen::Vector2d one_radian(1.0, 0.0);
  Eigen::Vector3d ours;
  Eigen::Vector3d ceres_sphere;
  ASSERT_TRUE(axis_manifold.Plus(pole.data(), one_radian.data(), ours.data()));
  ASSERT_TRUE(sphere_manifold.Plus(
      pole.data(), one_radian.data(), ceres_sphere.data()));
  EXPECT_NEAR(ours.z(), std::cos(1.0), 1e-15);
  EXPECT_NEAR(ceres_sphere.z(), std::cos(0.5), 1e-15);
}

TEST(AxisManifoldTest, PlusOutputIsUnitNorm) {
  const AxisManifold manifold;
  testing::TestRandom random(16);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 1000; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    // Any step, including ones longer than pi, and a slightly non-unit input.
    for (const double scale : {1.0, 1.0 + 1e-6, 0.999}) {
      const Eigen::Vector3d x_scaled = scale * x;
      const Eigen::Vector2d delta = RandomDelta(random, 10.0);
      Eigen::Vector3d moved;
      ASSERT_TRUE(manifold.Plus(x_scaled.data(), delta.data(), moved.data()));
      EXPECT_NEAR(moved.norm(), 1.0, 1e-15);
    }
  }
}

TEST(AxisManifoldTest, MinusNormIsTheAngleBetweenThePoints) {
  const AxisManifold manifold;
  testing::TestRandom random(17);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 1000; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    // Random y over the whole sphere, plus y very close to x and to -x.
    const Eigen::Vector3d random_y = random.UnitVector();
    const Eigen::Vector3d offset = 1e-7 * random.UnitVector();
    for (const Eigen::Vector3d& y :
         {random_y,
          Eigen::Vector3d((x + offset).normalized()),
          Eigen::Vector3d((-x + offset).normalized()),
          x}) {
      Eigen::Vector2d difference;
      ASSERT_TRUE(manifold.Minus(y.data(), x.data(), difference.data()));
      ASSERT_TRUE(difference.allFinite());
      EXPECT_NEAR(difference.norm(), AngleBetween(x, y), 1e-13);
    }
  }
}

TEST(AxisManifoldTest, MinusAtTheAntipodeIsAFiniteHalfTurn) {
  const AxisManifold manifold;
  testing::TestRandom random(18);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 1000; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    const Eigen::Vector3d y = -x;
    Eigen::Vector2d difference;
    ASSERT_TRUE(manifold.Minus(y.data(), x.data(), difference.data()));
    ASSERT_TRUE(difference.allFinite());
    EXPECT_NEAR(difference.norm(), kPi, 1e-12);
    // Stepping back along it reaches the antipode.
    Eigen::Vector3d back;
    ASSERT_TRUE(manifold.Plus(x.data(), difference.data(), back.data()));
    EXPECT_LT((back - y).norm(), 1e-12);
  }
}

// Residuals measure axis errors with SphereLog in the same basis, so that a
// residual's tangent coordinates and the manifold's agree.
TEST(AxisManifoldTest, MinusMatchesSphereLog) {
  const AxisManifold manifold;
  testing::TestRandom random(21);
  std::vector<Eigen::Vector3d> points = SpecialPoints();
  for (int i = 0; i < 500; ++i) points.push_back(random.UnitVector());
  for (const Eigen::Vector3d& x : points) {
    SCOPED_TRACE("x = " + Describe(x));
    const Eigen::Vector3d near_x =
        (x + 1e-6 * random.UnitVector()).normalized();
    for (const Eigen::Vector3d& y :
         {RandomPointNotNearAntipode(random, x), near_x}) {
      Eigen::Vector2d difference;
      ASSERT_TRUE(manifold.Minus(y.data(), x.data(), difference.data()));
      EXPECT_LT((difference - SphereLog(x, y)).norm(), 1e-14);
    }
    // At y = -x the direction is arbitrary (it follows rounding in B(x)^T y),
    // so only the length, a half-turn, is comparable.
    const Eigen::Vector3d antipode = -x;
    Eigen::Vector2d difference;
    ASSERT_TRUE(manifold.Minus(antipode.data(), x.data(), difference.data()));
    EXPECT_NEAR(difference.norm(), SphereLog(x, antipode).norm(), 1e-14);
  }
}

TEST(AxisManifoldTest, JacobiansAreFiniteAndOrthonormalAtThePoles) {
  const AxisManifold manifold;
  for (const Eigen::Vector3d& x : SpecialPoints()) {
    SCOPED_TRACE("x = " + Describe(x));
    PlusJacobianMatrix plus_jacobian;
    MinusJacobianMatrix minus_jacobian;
    ASSERT_TRUE(manifold.PlusJacobian(x.data(), plus_jacobian.data()));
    ASSERT_TRUE(manifold.MinusJacobian(x.data(), minus_jacobian.data()));
    ASSERT_TRUE(plus_jacobian.allFinite());
    ASSERT_TRUE(minus_jacobian.allFinite());
    EXPECT_LT((plus_jacobian.transpose() * plus_jacobian -
               Eigen::Matrix2d::Identity())
                  .lpNorm<Eigen::Infinity>(),
              1e-15);
    EXPECT_LT((minus_jacobian * minus_jacobian.transpose() -
               Eigen::Matrix2d::Identity())
                  .lpNorm<Eigen::Infinity>(),
              1e-15);
    EXPECT_LT((plus_jacobian.transpose() * x).lpNorm<Eigen::Infinity>(), 1e-15);
    EXPECT_EQ(minus_jacobian, plus_jacobian.transpose());
    // The Jacobian is the documented public basis.
    EXPECT_EQ(plus_jacobian, PlusJacobianMatrix(TangentBasis(x)));
  }
}

// residual = axis - target (3 residuals); its minimum on the sphere is
// axis = target.
struct AlignAxisWithTarget {
  explicit AlignAxisWithTarget(const Eigen::Vector3d& target_in)
      : target(target_in) {}
  template <typename T>
  bool operator()(const T* axis, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = axis[i] - T(target[i]);
    return true;
  }
  Eigen::Vector3d target;
};

// Optimises a unit axis from `start` towards `target`; returns the result.
Eigen::Vector3d AlignAxis(const Eigen::Vector3d& start,
                          const Eigen::Vector3d& target,
                          ceres::Solver::Summary* summary) {
  Eigen::Vector3d axis = start;
  ceres::Problem problem;
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<AlignAxisWithTarget, 3, 3>(
          new AlignAxisWithTarget(target)),
      nullptr,
      axis.data());
  problem.SetManifold(axis.data(), new AxisManifold);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.logging_type = ceres::SILENT;
  ceres::Solve(options, &problem, summary);
  return axis;
}

TEST(AxisManifoldTest, CeresAlignsAnAxisWithATarget) {
  testing::TestRandom random(19);
  std::vector<Eigen::Vector3d> targets = {
      Eigen::Vector3d(0.0, 0.0, 1.0),
      Eigen::Vector3d(0.0, 0.0, -1.0),
      Eigen::Vector3d(1.0, 0.0, 0.0),
      Eigen::Vector3d(0.6, -0.8, 0.0),
  };
  for (int i = 0; i < 8; ++i) targets.push_back(random.UnitVector());
  for (const Eigen::Vector3d& target : targets) {
    // From the antipode's side (about 170 degrees away; the exact antipode is
    // a stationary point), from both poles and from the equator.
    const Eigen::Vector3d tilt = random.UnitVector();
    const Eigen::Vector3d away =
        (tilt - tilt.dot(target) * target).normalized();
    const Eigen::Vector3d antipode_side =
        (std::cos(kPi - 0.17) * target + std::sin(kPi - 0.17) * away)
            .normalized();
    const std::vector<Eigen::Vector3d> starts = {
        antipode_side,
        Eigen::Vector3d(0.0, 0.0, 1.0),
        Eigen::Vector3d(0.0, 0.0, -1.0),
        Eigen::Vector3d(0.0, 1.0, 0.0),
    };
    for (const Eigen::Vector3d& start : starts) {
      if (AngleBetween(start, target) > kPi - 0.1) continue;
      SCOPED_TRACE("target = " + Describe(target) +
                   ", start = " + Describe(start));
      ceres::Solver::Summary summary;
      const Eigen::Vector3d axis = AlignAxis(start, target, &summary);
      EXPECT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
      EXPECT_EQ(summary.termination_type, ceres::CONVERGENCE)
          << summary.BriefReport();
      EXPECT_NEAR(axis.norm(), 1.0, 1e-15);
      EXPECT_LT((axis - target).norm(), 1e-8) << summary.BriefReport();
    }
  }
}

}  // namespace
}  // namespace symba
