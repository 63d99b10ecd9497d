#include "symba/geometry/swing_twist.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "test_support/jet_check.h"
#include "test_support/random.h"

namespace symba {
namespace {

double TwistRotationDistance(const Eigen::Quaterniond& a,
                             const Eigen::Quaterniond& b) {
  return std::min((a.coeffs() - b.coeffs()).norm(),
                  (a.coeffs() + b.coeffs()).norm());
}

bool AllFinite(const Eigen::Quaterniond& q) { return q.coeffs().allFinite(); }

// A random unit vector perpendicular to unit `a` (to rounding: a second
// projection removes what the first leaves behind).
Eigen::Vector3d RandomPerpendicular(testing::TestRandom& random,
                                    const Eigen::Vector3d& a) {
  Eigen::Vector3d v;
  do {
    v = random.UnitVector();
    v -= v.dot(a) * a;
  } while (v.norm() < 0.1);
  v.normalize();
  v -= v.dot(a) * a;
  return v.normalized();
}

// The rotation angle in [0, pi] of a unit quaternion.
double RotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

// ---------------------------------------------------------------------------
// Swing-twist decomposition.

void ExpectValidDecomposition(const Eigen::Quaterniond& q,
                              const Eigen::Vector3d& axis,
                              const SwingTwist<double>& st) {
  ASSERT_TRUE(AllFinite(st.swing));
  ASSERT_TRUE(AllFinite(st.twist));
  ASSERT_TRUE(std::isfinite(st.twist_angle));
  // q == swing * twist as quaternions, not only as rotations.
  EXPECT_LT(((st.swing * st.twist).coeffs() - q.coeffs()).norm(), 1e-15);
  EXPECT_NEAR(st.swing.norm(), 1.0, 1e-15);
  EXPECT_NEAR(st.twist.norm(), 1.0, 1e-15);
  // The twist rotates about the axis; the swing about an axis perpendicular
  // to it.
  EXPECT_LT(st.twist.vec().cross(axis).norm(), 1e-15);
  EXPECT_NEAR(st.swing.vec().dot(axis), 0.0, 1e-15);
  // The angle is the twist's, signed by the right-hand rule about the axis.
  EXPECT_GT(st.twist_angle, -kPi);
  EXPECT_LE(st.twist_angle, kPi);
  EXPECT_LT(TwistRotationDistance(
                ExpSO3(Eigen::Vector3d(st.twist_angle * axis)), st.twist),
            1e-15);
}

TEST(SwingTwistTest, DecomposesRandomRotationsAboutRandomAxes) {
  testing::TestRandom random(51);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Vector3d axis = random.UnitVector();
    ExpectValidDecomposition(q, axis, DecomposeSwingTwist(q, axis));
  }
}

TEST(SwingTwistTest, SignedQuarterTurnsAreNotFolded) {
  testing::TestRandom random(52);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const Eigen::Quaterniond plus(Eigen::AngleAxisd(0.5 * kPi, axis));
    const Eigen::Quaterniond minus(Eigen::AngleAxisd(-0.5 * kPi, axis));
    EXPECT_NEAR(TwistAngle(plus, axis), 0.5 * kPi, 1e-15);
    EXPECT_NEAR(TwistAngle(minus, axis), -0.5 * kPi, 1e-15);
    // About the opposite axis the signs swap.
    EXPECT_NEAR(TwistAngle(plus, Eigen::Vector3d(-axis)), -0.5 * kPi, 1e-15);
    EXPECT_NEAR(TwistAngle(minus, Eigen::Vector3d(-axis)), 0.5 * kPi, 1e-15);
  }
}

TEST(SwingTwistTest, SwingTimesKnownTwistRecoversTheTwistAngle) {
  testing::TestRandom random(53);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const double twist_angle = random.Uniform(-kPi, kPi);
    // Swings of any angle below pi about any perpendicular axis.
    const double swing_angle = random.Uniform(-3.1, 3.1);
    const Eigen::Quaterniond swing(
        Eigen::AngleAxisd(swing_angle, RandomPerpendicular(random, axis)));
    const Eigen::Quaterniond twist(Eigen::AngleAxisd(twist_angle, axis));
    const Eigen::Quaterniond q = swing * twist;
    const SwingTwist<double> st = DecomposeSwingTwist(q, axis);
    ExpectValidDecomposition(q, axis, st);
    // [q.w, q.vec . axis] = cos(swing / 2) [cos(twist / 2), sin(twist / 2)]:
    // the rounding of q is amplified by 1 / cos(swing / 2).
    const double amplification = 1.0 / std::cos(0.5 * swing_angle);
    EXPECT_NEAR(st.twist_angle, twist_angle, 4e-15 * amplification)
        << "swing " << swing_angle << " twist " << twist_angle;
    EXPECT_LT(TwistRotationDistance(st.twist, twist), 2e-15 * amplification);
    EXPECT_LT(TwistRotationDistance(st.swing, swing), 2e-15 * amplification);
    // -q is the same rotation and has the same decomposition.
    const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_EQ(TwistAngle(minus_q, axis), st.twist_angle);
  }
}

TEST(SwingTwistTest, PureTwistHasIdentitySwing) {
  testing::TestRandom random(54);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const double angle = random.Uniform(-kPi, kPi);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis));
    const SwingTwist<double> st = DecomposeSwingTwist(q, axis);
    EXPECT_NEAR(st.twist_angle, angle, 1e-15);
    EXPECT_LT(TwistRotationDistance(st.swing, Eigen::Quaterniond::Identity()),
              1e-15);
  }
}

TEST(SwingTwistTest, PureSwingHasZeroTwist) {
  testing::TestRandom random(55);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const double angle = random.Uniform(-3.1, 3.1);
    const Eigen::Quaterniond q(
        Eigen::AngleAxisd(angle, RandomPerpendicular(random, axis)));
    const SwingTwist<double> st = DecomposeSwingTwist(q, axis);
    const double amplification = 1.0 / std::cos(0.5 * angle);
    EXPECT_NEAR(st.twist_angle, 0.0, 4e-15 * amplification);
    EXPECT_LT(TwistRotationDistance(st.twist, Eigen::Quaterniond::Identity()),
              2e-15 * amplification);
  }
}

TEST(SwingTwistTest, IdentityDecomposesIntoIdentities) {
  const Eigen::Vector3d axis(0.0, 0.6, 0.8);
  const SwingTwist<double> st =
      DecomposeSwingTwist(Eigen::Quaterniond::Identity(), axis);
  EXPECT_EQ(st.twist_angle, 0.0);
  EXPECT_EQ(st.twist.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(st.swing.coeffs(), Eigen::Quaterniond::Identity().coeffs());
}

TEST(SwingTwistTest, HalfTurnAboutPerpendicularAxisIsDegenerateButFinite) {
  testing::TestRandom random(56);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const Eigen::Vector3d b = RandomPerpendicular(random, axis);
    // Exactly w = 0 and v.axis = 0 up to rounding of the dot product.
    const Eigen::Quaterniond q(0.0, b.x(), b.y(), b.z());
    const SwingTwist<double> st = DecomposeSwingTwist(q, axis);
    EXPECT_EQ(st.twist_angle, 0.0);
    EXPECT_EQ(st.twist.coeffs(), Eigen::Quaterniond::Identity().coeffs());
    EXPECT_EQ(st.swing.coeffs(), q.coeffs());
    EXPECT_EQ(TwistAngle(q, axis), 0.0);
  }
  // The axis-aligned case, where the dot product is exactly zero.
  const Eigen::Quaterniond half_turn_x(0.0, 1.0, 0.0, 0.0);
  const SwingTwist<double> st =
      DecomposeSwingTwist(half_turn_x, Eigen::Vector3d::UnitZ().eval());
  EXPECT_EQ(st.twist_angle, 0.0);
  EXPECT_EQ(st.twist.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(st.swing.coeffs(), half_turn_x.coeffs());
}

TEST(SwingTwistTest, TwistOfExactlyPiIsPlusPi) {
  testing::TestRandom random(57);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d a = random.UnitVector();
    // [0, a], [0, -a] and [-0, a] are all the half-turn about a.
    for (const Eigen::Quaterniond& q :
         {Eigen::Quaterniond(0.0, a.x(), a.y(), a.z()),
          Eigen::Quaterniond(0.0, -a.x(), -a.y(), -a.z()),
          Eigen::Quaterniond(-0.0, a.x(), a.y(), a.z()),
          Eigen::Quaterniond(-0.0, -a.x(), -a.y(), -a.z())}) {
      const SwingTwist<double> st = DecomposeSwingTwist(q, a);
      EXPECT_EQ(st.twist_angle, kPi);
      EXPECT_LT(TwistRotationDistance(st.twist, q), 1e-15);
      EXPECT_LT(TwistRotationDistance(st.swing, Eigen::Quaterniond::Identity()),
                1e-15);
    }
    // Via AngleAxis, w = cos(pi / 2) = 6e-17 > 0: pi to rounding.
    const Eigen::Quaterniond q(Eigen::AngleAxisd(kPi, a));
    EXPECT_NEAR(TwistAngle(q, a), kPi, 1e-15);
    EXPECT_LE(TwistAngle(q, a), kPi);
  }
  // With a swing in front, the twist of pi is still +pi.
  const Eigen::Quaterniond swing(
      Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond twist(0.0, 0.0, 0.0, -1.0);  // half-turn about z
  EXPECT_NEAR(TwistAngle(Eigen::Quaterniond(swing * twist),
                         Eigen::Vector3d::UnitZ().eval()),
              kPi,
              1e-15);
}

TEST(SwingTwistTest, TwistAboutOppositeAxisNegatesTheAngle) {
  testing::TestRandom random(58);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Vector3d axis = random.UnitVector();
    const double angle = TwistAngle(q, axis);
    if (std::abs(angle) > 3.1) continue;  // +-pi are the same
    EXPECT_NEAR(TwistAngle(q, Eigen::Vector3d(-axis)), -angle, 1e-14);
  }
}

struct TwistAngleOfFlat {
  // x = [q.x, q.y, q.z, q.w, axis.x, axis.y, axis.z]
  template <typename T>
  Eigen::Matrix<T, 1, 1> operator()(const Eigen::Matrix<T, 7, 1>& x) const {
    const Eigen::Quaternion<T> q(x(3), x(0), x(1), x(2));
    return Eigen::Matrix<T, 1, 1>(
        TwistAngle(q, Vector3<T>(x.template tail<3>())));
  }
};

TEST(SwingTwistTest, TwistAngleJetDerivativesMatchNumeric) {
  testing::TestRandom random(59);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Vector3d axis = random.UnitVector();
    // Differentiable where the twist is defined and not a half-turn.
    if (std::abs(TwistAngle(q, axis)) > 3.0) continue;
    if (std::abs(q.w()) < 1e-3) continue;
    Eigen::Matrix<double, 7, 1> x;
    x << q.coeffs(), axis;
    EXPECT_TRUE(testing::JetMatchesNumeric(TwistAngleOfFlat(), x, 1e-7));
  }
  // A pure twist and a pure swing.
  const Eigen::Vector3d axis = random.UnitVector();
  for (const Eigen::Quaterniond& q :
       {Eigen::Quaterniond(Eigen::AngleAxisd(1.0, axis)),
        Eigen::Quaterniond(
            Eigen::AngleAxisd(1.0, RandomPerpendicular(random, axis))),
        Eigen::Quaterniond::Identity()}) {
    Eigen::Matrix<double, 7, 1> x;
    x << q.coeffs(), axis;
    EXPECT_TRUE(testing::JetMatchesNumeric(TwistAngleOfFlat(), x, 1e-7));
  }
}

TEST(SwingTwistTest, DegenerateDecompositionHasFiniteJets) {
  using Jet = ceres::Jet<double, 4>;
  const Eigen::Quaternion<Jet> q(
      Jet(0.0, 3), Jet(1.0, 0), Jet(0.0, 1), Jet(0.0, 2));
  const Vector3<Jet> axis(Jet(0.0), Jet(0.0), Jet(1.0));
  const SwingTwist<Jet> st = DecomposeSwingTwist(q, axis);
  EXPECT_EQ(st.twist_angle.a, 0.0);
  EXPECT_TRUE(st.twist_angle.v.allFinite());
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(std::isfinite(st.swing.coeffs()(i).a));
    EXPECT_TRUE(st.swing.coeffs()(i).v.allFinite());
  }
}

// ---------------------------------------------------------------------------
// Minimal rotation between two unit vectors.

TEST(MinimalRotationTest, MapsFromToToOnRandomInputs) {
  testing::TestRandom random(61);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d u = random.UnitVector();
    const Eigen::Vector3d v = random.UnitVector();
    const Eigen::Quaterniond q = MinimalRotation(u, v);
    ASSERT_TRUE(AllFinite(q));
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_LT((q * u - v).norm(), 2e-15);
    // Least angle: acos(u.v), about u x v.
    EXPECT_NEAR(RotationAngle(q), std::acos(u.dot(v)), 1e-13);
    const Eigen::Vector3d n = u.cross(v).normalized();
    EXPECT_LT((q.vec().normalized() - n).norm(), 1e-13);
    EXPECT_GE(q.w(), 0.0);
  }
}

TEST(MinimalRotationTest, EqualVectorsGiveExactIdentity) {
  testing::TestRandom random(62);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d u = random.UnitVector();
    const Eigen::Quaterniond q = MinimalRotation(u, u);
    EXPECT_EQ(q.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  }
}

TEST(MinimalRotationTest, OppositeVectorsGiveAHalfTurn) {
  testing::TestRandom random(63);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d u = random.UnitVector();
    const Eigen::Vector3d v = -u;
    const Eigen::Quaterniond q = MinimalRotation(u, v);
    ASSERT_TRUE(AllFinite(q));
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_EQ(q.w(), 0.0);
    EXPECT_NEAR(q.vec().dot(u), 0.0, 1e-15);
    EXPECT_LT((q * u - v).norm(), 1e-15);
  }
  for (const Eigen::Vector3d& u :
       {Eigen::Vector3d(Eigen::Vector3d::UnitX()),
        Eigen::Vector3d(Eigen::Vector3d::UnitY()),
        Eigen::Vector3d(Eigen::Vector3d::UnitZ()),
        Eigen::Vector3d(-Eigen::Vector3d::UnitZ()),
        Eigen::Vector3d(1.0, 1.0, 1.0).normalized()}) {
    const Eigen::Quaterniond q = MinimalRotation(u, Eigen::Vector3d(-u));
    ASSERT_TRUE(AllFinite(q));
    EXPECT_LT((q * u + u).norm(), 1e-15);
  }
}

TEST(MinimalRotationTest, NearlyOppositeVectorsStillMapFromToTo) {
  testing::TestRandom random(64);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d u = random.UnitVector();
    const Eigen::Vector3d p = RandomPerpendicular(random, u);
    // v is -u tilted by delta towards p: the angle from u is pi - delta.
    for (const double delta :
         {1e-1, 1e-3, 1e-5, 1e-6, 1.4e-6, 1e-7, 1e-8, 1e-9, 1e-11, 1e-13}) {
      const Eigen::Vector3d v = -std::cos(delta) * u + std::sin(delta) * p;
      const Eigen::Quaterniond q = MinimalRotation(u, v);
      ASSERT_TRUE(AllFinite(q)) << "delta " << delta;
      EXPECT_NEAR(q.norm(), 1.0, 1e-15);
      EXPECT_LT((q * u - v).norm(), 1e-6) << "delta " << delta;
      // Not only within 1e-6: to rounding, as for any other pair.
      EXPECT_LT((q * u - v).norm(), 1e-14) << "delta " << delta;
      EXPECT_NEAR(RotationAngle(q), kPi - delta, 1e-14) << "delta " << delta;
    }
  }
}

TEST(MinimalRotationTest, NearlyEqualVectorsMapFromToTo) {
  testing::TestRandom random(65);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d u = random.UnitVector();
    const Eigen::Vector3d p = RandomPerpendicular(random, u);
    for (const double delta : {1e-3, 1e-6, 1e-9, 1e-12}) {
      const Eigen::Vector3d v = std::cos(delta) * u + std::sin(delta) * p;
      const Eigen::Quaterniond q = MinimalRotation(u, v);
      EXPECT_LT((q * u - v).norm(), 1e-15) << "delta " << delta;
      EXPECT_NEAR(RotationAngle(q), delta, 1e-15) << "delta " << delta;
    }
  }
}

TEST(MinimalRotationTest, AnyPerpendicularIsAPerpendicularUnitVector) {
  testing::TestRandom random(66);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d u = random.UnitVector();
    const Eigen::Vector3d p = AnyPerpendicular(u);
    EXPECT_NEAR(p.norm(), 1.0, 1e-15);
    EXPECT_NEAR(p.dot(u), 0.0, 1e-15);
  }
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
    EXPECT_EQ(AnyPerpendicular(e).dot(e), 0.0);
    EXPECT_EQ(AnyPerpendicular(Eigen::Vector3d(-e)).dot(e), 0.0);
  }
}

struct MinimalRotationOfFlat {
  // x = [from; to]
  template <typename T>
  Eigen::Matrix<T, 4, 1> operator()(const Eigen::Matrix<T, 6, 1>& x) const {
    return MinimalRotation(Vector3<T>(x.template head<3>()),
                           Vector3<T>(x.template tail<3>()))
        .coeffs();
  }
};

TEST(MinimalRotationTest, JetDerivativesMatchNumeric) {
  testing::TestRandom random(67);
  for (int i = 0; i < 300; ++i) {
    Eigen::Matrix<double, 6, 1> x;
    x << random.UnitVector(), random.UnitVector();
    if (x.head<3>().dot(x.tail<3>()) < -0.99) continue;
    EXPECT_TRUE(testing::JetMatchesNumeric(MinimalRotationOfFlat(), x, 1e-7));
  }
  // Equal vectors (the identity) and a nearly opposite pair.
  const Eigen::Vector3d u = random.UnitVector();
  const Eigen::Vector3d p = RandomPerpendicular(random, u);
  for (const Eigen::Vector3d& v :
       {u, Eigen::Vector3d(-std::cos(1e-2) * u + std::sin(1e-2) * p)}) {
    Eigen::Matrix<double, 6, 1> x;
    x << u, v;
    EXPECT_TRUE(
        testing::JetMatchesNumeric(MinimalRotationOfFlat(), x, 1e-6, 1e-7));
  }
}

}  // namespace
}  // namespace symba
