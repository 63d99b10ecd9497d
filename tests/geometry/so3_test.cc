#include "symba/geometry/so3.h"

#include <cmath>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "test_support/jet_check.h"
#include "test_support/random.h"

namespace symba {
namespace {

constexpr double kPiTest = 3.14159265358979323846;

// The angles the issue singles out: zero, tiny, both sides of the Taylor
// switches (exp: |w|^2 = 1e-8, angle 1e-4; log: |q.vec|^2 = 1e-8, angle
// 2e-4), ordinary, and near / at pi.
const std::vector<double>& EdgeAngles() {
  static const std::vector<double> angles = {0.0,
                                             1e-10,
                                             1e-7,
                                             1e-5,
                                             1e-4 * (1.0 - 1e-9),
                                             1e-4 * (1.0 + 1e-9),
                                             2e-4 * (1.0 - 1e-9),
                                             2e-4 * (1.0 + 1e-9),
                                             1e-3,
                                             0.5,
                                             2.0,
                                             kPiTest - 1e-6,
                                             kPiTest - 1e-9,
                                             kPiTest};
  return angles;
}

// The quaternion with memory coefficients [x, y, z, w].
template <typename T>
Eigen::Quaternion<T> QuaternionFromCoeffs(const Eigen::Matrix<T, 4, 1>& c) {
  return Eigen::Quaternion<T>(c(3), c(0), c(1), c(2));
}

// Distance between the rotations of two unit quaternions (q ~ -q).
double RotationDistance(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return std::min((a.coeffs() - b.coeffs()).norm(),
                  (a.coeffs() + b.coeffs()).norm());
}

TEST(So3Test, HatIsTheCrossProductMatrix) {
  testing::TestRandom random(11);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d w = random.NormalVector(2.0);
    const Eigen::Vector3d v = random.NormalVector(2.0);
    const Eigen::Matrix3d W = Hat(w);
    EXPECT_LT((W * v - w.cross(v)).norm(), 1e-14);
    EXPECT_EQ(W + W.transpose(), Eigen::Matrix3d::Zero());
  }
}

TEST(So3Test, ExpMatchesEigenAngleAxisOnRandomInputs) {
  testing::TestRandom random(1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const double angle = random.Uniform(0.0, kPiTest);
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    const Eigen::Quaterniond actual = ExpSO3(Eigen::Vector3d(angle * axis));
    EXPECT_LT(expected.angularDistance(actual), 1e-12) << "angle " << angle;
    // Both use the representative with w >= 0 for angles below pi.
    EXPECT_LT((expected.coeffs() - actual.coeffs()).norm(), 1e-15)
        << "angle " << angle;
    EXPECT_NEAR(actual.norm(), 1.0, 1e-15);
  }
}

TEST(So3Test, ExpMatchesEigenAngleAxisAtEdgeAngles) {
  testing::TestRandom random(2);
  for (const double angle : EdgeAngles()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d axis = random.UnitVector();
      const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
      const Eigen::Quaterniond actual = ExpSO3(Eigen::Vector3d(angle * axis));
      EXPECT_LT((expected.coeffs() - actual.coeffs()).norm(), 1e-15)
          << "angle " << angle;
      // The imaginary part is exact to relative precision even when tiny.
      if (angle > 0.0) {
        EXPECT_NEAR(actual.vec().norm(),
                    std::sin(0.5 * angle),
                    1e-15 * std::sin(0.5 * angle))
            << "angle " << angle;
        EXPECT_LT(actual.vec().normalized().cross(axis).norm(), 1e-15);
      }
    }
  }
}

TEST(So3Test, ExpOfZeroIsExactlyIdentity) {
  const Eigen::Quaterniond q = ExpSO3(Eigen::Vector3d::Zero().eval());
  EXPECT_EQ(q.w(), 1.0);
  EXPECT_EQ(q.x(), 0.0);
  EXPECT_EQ(q.y(), 0.0);
  EXPECT_EQ(q.z(), 0.0);
}

TEST(So3Test, ExpOfTinyAngleKeepsRelativePrecision) {
  const Eigen::Vector3d w(1e-10, -2e-10, 3e-10);
  const Eigen::Quaterniond q = ExpSO3(w);
  EXPECT_EQ(q.w(), 1.0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(q.vec()(i), 0.5 * w(i), 1e-16 * std::abs(w(i)));
  }
}

TEST(So3Test, ExpOfPiIsAHalfTurn) {
  testing::TestRandom random(3);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const Eigen::Quaterniond q = ExpSO3(Eigen::Vector3d(kPiTest * axis));
    // |pi * axis| is pi to a few ulps, so w = cos(|w| / 2) is a few 1e-16.
    EXPECT_NEAR(q.w(), 0.0, 1e-15);
    EXPECT_LT((q.vec() - axis).norm(), 1e-15);
  }
}

TEST(So3Test, LogMatchesEigenAngleAxisOnRandomInputs) {
  testing::TestRandom random(4);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::AngleAxisd expected(q);
    const Eigen::Vector3d w = LogSO3(q);
    EXPECT_LT((w - expected.angle() * expected.axis()).norm(), 1e-13);
    EXPECT_LE(w.norm(), kPiTest);
  }
}

TEST(So3Test, LogMatchesEigenAngleAxisAtEdgeAngles) {
  testing::TestRandom random(5);
  for (const double angle : EdgeAngles()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d axis = random.UnitVector();
      const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis));
      const Eigen::AngleAxisd expected(q);
      const Eigen::Vector3d w = LogSO3(q);
      const Eigen::Vector3d w_expected = expected.angle() * expected.axis();
      if (angle < kPiTest) {
        EXPECT_LT((w - w_expected).norm(), 1e-15 + 1e-15 * angle)
            << "angle " << angle;
      } else {
        // At pi, w and -w are both logarithms.
        EXPECT_LT(std::min((w - w_expected).norm(), (w + w_expected).norm()),
                  1e-15)
            << "angle " << angle;
      }
    }
  }
}

TEST(So3Test, LogOfIdentityIsExactlyZero) {
  EXPECT_EQ(LogSO3(Eigen::Quaterniond::Identity()), Eigen::Vector3d::Zero());
  // -identity is the same rotation.
  const Eigen::Quaterniond minus_identity(-1.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(LogSO3(minus_identity), Eigen::Vector3d::Zero());
}

TEST(So3Test, LogIsTheSameForBothSignsOfTheQuaternion) {
  testing::TestRandom random(6);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_EQ(LogSO3(q), LogSO3(minus_q));
  }
}

TEST(So3Test, LogOfExactHalfTurnHasNormPiAndExpsBack) {
  testing::TestRandom random(7);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    // w exactly 0, either sign of the axis, and w = -0.0.
    for (const Eigen::Quaterniond& q :
         {Eigen::Quaterniond(0.0, axis.x(), axis.y(), axis.z()),
          Eigen::Quaterniond(0.0, -axis.x(), -axis.y(), -axis.z()),
          Eigen::Quaterniond(-0.0, axis.x(), axis.y(), axis.z()),
          Eigen::Quaterniond(Eigen::AngleAxisd(kPiTest, axis)),
          Eigen::Quaterniond(Eigen::AngleAxisd(-kPiTest, axis))}) {
      const Eigen::Vector3d w = LogSO3(q);
      ASSERT_TRUE(w.allFinite());
      EXPECT_NEAR(w.norm(), kPiTest, 1e-15);
      EXPECT_LT(w.normalized().cross(axis).norm(), 1e-15);
      EXPECT_LT(RotationDistance(ExpSO3(w), q), 1e-15);
    }
  }
}

TEST(So3Test, ExpOfLogIsTheSameRotationOnRandomInputs) {
  testing::TestRandom random(8);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Quaterniond back = ExpSO3(LogSO3(q));
    EXPECT_LT(RotationDistance(back, q), 1e-15);
    // ExpSO3 returns w >= 0, so back == q up to the sign making w >= 0.
    EXPECT_GE(back.w(), 0.0);
  }
}

TEST(So3Test, LogOfExpIsIdentityOnRandomInputs) {
  testing::TestRandom random(9);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const double angle = random.Uniform(0.0, kPiTest);
    const Eigen::Vector3d w = angle * axis;
    EXPECT_LT((LogSO3(ExpSO3(w)) - w).norm(), 2e-15) << "angle " << angle;
  }
  // Small rotation vectors of every scale.
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d w =
        std::pow(10.0, random.Uniform(-12.0, 0.0)) * random.UnitVector();
    EXPECT_LT((LogSO3(ExpSO3(w)) - w).norm(), 1e-15 * w.norm())
        << "norm " << w.norm();
  }
}

TEST(So3Test, RoundTripsAtEdgeAngles) {
  testing::TestRandom random(10);
  for (const double angle : EdgeAngles()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d w = angle * random.UnitVector();
      const Eigen::Quaterniond q = ExpSO3(w);
      const Eigen::Vector3d log_q = LogSO3(q);
      EXPECT_LT(RotationDistance(ExpSO3(log_q), q), 1e-15) << "angle " << angle;
      if (angle < kPiTest) {
        EXPECT_LT((log_q - w).norm(), 1e-15 + 1e-15 * angle)
            << "angle " << angle;
      } else {
        EXPECT_NEAR(log_q.norm(), kPiTest, 1e-15);
        EXPECT_LT(std::min((log_q - w).norm(), (log_q + w).norm()), 1e-15);
      }
    }
  }
}

TEST(So3Test, MatrixLogAgreesWithQuaternionLog) {
  testing::TestRandom random(12);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Matrix3d R = q.toRotationMatrix();
    EXPECT_LT((LogSO3(R) - LogSO3(q)).norm(), 1e-13);
  }
  for (const double angle : EdgeAngles()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Quaterniond q = random.RotationOfAngle(angle);
      const Eigen::Vector3d from_matrix = LogSO3(q.toRotationMatrix());
      const Eigen::Vector3d from_quaternion = LogSO3(q);
      const double tolerance = 1e-13;
      if (angle < kPiTest) {
        EXPECT_LT((from_matrix - from_quaternion).norm(), tolerance)
            << "angle " << angle;
      } else {
        EXPECT_LT(std::min((from_matrix - from_quaternion).norm(),
                           (from_matrix + from_quaternion).norm()),
                  tolerance);
      }
      EXPECT_LT((ExpSO3(from_matrix).toRotationMatrix() - q.toRotationMatrix())
                    .norm(),
                1e-14)
          << "angle " << angle;
    }
  }
  EXPECT_EQ(LogSO3(Eigen::Matrix3d::Identity().eval()),
            Eigen::Vector3d::Zero());
}

// ---------------------------------------------------------------------------
// Derivatives through ceres::Jet.

struct ExpSO3Coeffs {
  template <typename T>
  Eigen::Matrix<T, 4, 1> operator()(const Eigen::Matrix<T, 3, 1>& w) const {
    return ExpSO3(Vector3<T>(w)).coeffs();
  }
};

struct LogSO3OfCoeffs {
  template <typename T>
  Eigen::Matrix<T, 3, 1> operator()(const Eigen::Matrix<T, 4, 1>& c) const {
    return LogSO3(QuaternionFromCoeffs(c));
  }
};

TEST(So3Test, ExpJetDerivativesMatchNumericOnRandomInputs) {
  testing::TestRandom random(13);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d w = random.Uniform(0.0, 3.0) * random.UnitVector();
    EXPECT_TRUE(testing::JetMatchesNumeric(ExpSO3Coeffs(), w, 1e-8));
  }
}

TEST(So3Test, ExpJetDerivativesMatchNumericAtEdgeAngles) {
  testing::TestRandom random(14);
  for (const double angle : EdgeAngles()) {
    for (int i = 0; i < 5; ++i) {
      const Eigen::Vector3d w = angle * random.UnitVector();
      EXPECT_TRUE(testing::JetMatchesNumeric(ExpSO3Coeffs(), w, 1e-8))
          << "angle " << angle;
    }
  }
}

TEST(So3Test, ExpJacobianAtZeroIsHalfIdentity) {
  const Eigen::Matrix<double, 4, 3> J =
      testing::JetJacobian(ExpSO3Coeffs(), Eigen::Vector3d::Zero().eval());
  Eigen::Matrix<double, 4, 3> expected = Eigen::Matrix<double, 4, 3>::Zero();
  expected.topRows<3>() = 0.5 * Eigen::Matrix3d::Identity();
  EXPECT_EQ(J, expected);
}

TEST(So3Test, LogJetDerivativesMatchNumericOnRandomInputs) {
  testing::TestRandom random(15);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    // Stay clear of w = 0, where the sign flip makes the log (of the raw
    // coefficients) discontinuous.
    if (std::abs(q.w()) < 1e-3) continue;
    EXPECT_TRUE(testing::JetMatchesNumeric(
        LogSO3OfCoeffs(), Eigen::Vector4d(q.coeffs()), 1e-7));
  }
}

TEST(So3Test, LogJetDerivativesMatchNumericAtEdgeAngles) {
  testing::TestRandom random(16);
  for (const double angle : EdgeAngles()) {
    // Differentiable below pi; near pi the step must stay below w = cos(a/2).
    if (angle > 3.0) continue;
    for (int i = 0; i < 5; ++i) {
      const Eigen::Quaterniond q = random.RotationOfAngle(angle);
      EXPECT_TRUE(testing::JetMatchesNumeric(
          LogSO3OfCoeffs(), Eigen::Vector4d(q.coeffs()), 1e-7))
          << "angle " << angle;
    }
  }
  for (const double angle : {kPiTest - 1e-2, kPiTest - 1e-4}) {
    const Eigen::Quaterniond q = random.RotationOfAngle(angle);
    EXPECT_TRUE(testing::JetMatchesNumeric(
        LogSO3OfCoeffs(), Eigen::Vector4d(q.coeffs()), 1e-6, 1e-8))
        << "angle " << angle;
  }
}

TEST(So3Test, LogJacobianAtIdentityIsTwiceIdentity) {
  const Eigen::Vector4d identity(0.0, 0.0, 0.0, 1.0);
  const Eigen::Matrix<double, 3, 4> J =
      testing::JetJacobian(LogSO3OfCoeffs(), identity);
  Eigen::Matrix<double, 3, 4> expected = Eigen::Matrix<double, 3, 4>::Zero();
  expected.leftCols<3>() = 2.0 * Eigen::Matrix3d::Identity();
  EXPECT_EQ(J, expected);
  EXPECT_TRUE(testing::JetMatchesNumeric(LogSO3OfCoeffs(), identity, 1e-8));
}

TEST(So3Test, LogJacobianIsTheInverseOfExpJacobianOnTheTangent) {
  // d log / d q * d exp / d w = I: a check independent of finite differences.
  testing::TestRandom random(17);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d w = random.Uniform(0.0, 3.0) * random.UnitVector();
    const Eigen::Matrix<double, 4, 3> d_exp =
        testing::JetJacobian(ExpSO3Coeffs(), w);
    const Eigen::Matrix<double, 3, 4> d_log = testing::JetJacobian(
        LogSO3OfCoeffs(), Eigen::Vector4d(ExpSO3(w).coeffs()));
    EXPECT_LT((d_log * d_exp - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  }
}

// ---------------------------------------------------------------------------
// The Jet check helper itself must be able to fail.

struct WrongDerivative {
  template <typename T>
  Eigen::Matrix<T, 1, 1> operator()(const Eigen::Matrix<T, 1, 1>& x) const {
    if constexpr (std::is_same_v<T, double>) {
      return Eigen::Matrix<T, 1, 1>(x(0) * x(0));
    } else {
      // Same value, derivative x instead of 2x.
      T y = x(0) * x(0);
      y.v *= 0.5;
      return Eigen::Matrix<T, 1, 1>(y);
    }
  }
};

struct CorrectDerivative {
  template <typename T>
  Eigen::Matrix<T, 1, 1> operator()(const Eigen::Matrix<T, 1, 1>& x) const {
    using std::sin;
    return Eigen::Matrix<T, 1, 1>(sin(x(0)) * x(0));
  }
};

TEST(JetCheckTest, DetectsAWrongDerivativeAndAcceptsARightOne) {
  const Eigen::Matrix<double, 1, 1> x(0.7);
  EXPECT_FALSE(testing::JetMatchesNumeric(WrongDerivative(), x, 1e-7));
  EXPECT_TRUE(testing::JetMatchesNumeric(CorrectDerivative(), x, 1e-9));
  const Eigen::Matrix<double, 1, 1> J =
      testing::JetJacobian(CorrectDerivative(), x);
  EXPECT_NEAR(J(0, 0), std::cos(0.7) * 0.7 + std::sin(0.7), 1e-15);
}

}  // namespace
}  // namespace symba
