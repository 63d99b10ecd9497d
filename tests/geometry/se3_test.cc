#include "symba/geometry/se3.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "symba/geometry/rigid3.h"
#include "symba/geometry/so3.h"
#include "test_support/jet_check.h"
#include "test_support/random.h"

namespace symba {
namespace {

constexpr double kSe3Pi = 3.14159265358979323846;

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

// Zero, tiny, both sides of the series switch (|w|^2 = 1e-4, angle 1e-2)
// and of the SO(3) log's switch (angle 2e-4), ordinary, near / at pi.
const std::vector<double>& Se3EdgeAngles() {
  static const std::vector<double> angles = {0.0,
                                             1e-10,
                                             1e-7,
                                             1e-5,
                                             2e-4 * (1.0 - 1e-9),
                                             2e-4 * (1.0 + 1e-9),
                                             1e-2 * (1.0 - 1e-9),
                                             1e-2 * (1.0 + 1e-9),
                                             0.3,
                                             2.0,
                                             kSe3Pi - 1e-6,
                                             kSe3Pi - 1e-9,
                                             kSe3Pi};
  return angles;
}

Vector6d Twist(const Eigen::Vector3d& rho, const Eigen::Vector3d& omega) {
  Vector6d xi;
  xi << rho, omega;
  return xi;
}

// V(w) = sum_k W^k / (k + 1)!, summed in long double: a reference that
// shares nothing with the closed form under test.
Eigen::Matrix3d LeftJacobianBySeries(const Eigen::Vector3d& omega) {
  using Matrix3l = Eigen::Matrix<long double, 3, 3>;
  const Matrix3l W = Hat(Eigen::Vector3d(omega)).cast<long double>();
  Matrix3l sum = Matrix3l::Identity();
  Matrix3l term = Matrix3l::Identity();  // W^k / (k + 1)!
  for (int k = 1; k < 60; ++k) {
    term = term * W / static_cast<long double>(k + 1);
    sum += term;
  }
  return sum.cast<double>();
}

double Se3RotationDistance(const Eigen::Quaterniond& a,
                           const Eigen::Quaterniond& b) {
  return std::min((a.coeffs() - b.coeffs()).norm(),
                  (a.coeffs() + b.coeffs()).norm());
}

TEST(Se3Test, LeftJacobianMatchesItsSeries) {
  testing::TestRandom random(21);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d omega =
        random.Uniform(0.0, kSe3Pi) * random.UnitVector();
    EXPECT_LT((SO3LeftJacobian(omega) - LeftJacobianBySeries(omega)).norm(),
              1e-14)
        << "angle " << omega.norm();
  }
  for (const double angle : Se3EdgeAngles()) {
    const Eigen::Vector3d omega = angle * random.UnitVector();
    EXPECT_LT((SO3LeftJacobian(omega) - LeftJacobianBySeries(omega)).norm(),
              1e-14)
        << "angle " << angle;
  }
}

TEST(Se3Test, LeftJacobianOfZeroIsExactlyIdentity) {
  EXPECT_EQ(SO3LeftJacobian(Eigen::Vector3d::Zero().eval()),
            Eigen::Matrix3d::Identity());
  EXPECT_EQ(SO3LeftJacobianInverse(Eigen::Vector3d::Zero().eval()),
            Eigen::Matrix3d::Identity());
}

TEST(Se3Test, LeftJacobianTimesInverseIsIdentity) {
  testing::TestRandom random(22);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d omega =
        random.Uniform(0.0, kSe3Pi) * random.UnitVector();
    const Eigen::Matrix3d product =
        SO3LeftJacobian(omega) * SO3LeftJacobianInverse(omega);
    EXPECT_LT((product - Eigen::Matrix3d::Identity()).norm(), 1e-14)
        << "angle " << omega.norm();
  }
  for (const double angle : Se3EdgeAngles()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d omega = angle * random.UnitVector();
      const Eigen::Matrix3d V = SO3LeftJacobian(omega);
      const Eigen::Matrix3d V_inv = SO3LeftJacobianInverse(omega);
      EXPECT_LT((V * V_inv - Eigen::Matrix3d::Identity()).norm(), 1e-14)
          << "angle " << angle;
      EXPECT_LT((V_inv * V - Eigen::Matrix3d::Identity()).norm(), 1e-14)
          << "angle " << angle;
    }
  }
}

TEST(Se3Test, LeftJacobianFixesTheRotationAxis) {
  // V(w) w = w and V^-1(w) w = w (W w = 0).
  testing::TestRandom random(23);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d omega =
        random.Uniform(0.0, kSe3Pi) * random.UnitVector();
    EXPECT_LT((SO3LeftJacobian(omega) * omega - omega).norm(), 1e-14);
    EXPECT_LT((SO3LeftJacobianInverse(omega) * omega - omega).norm(), 1e-14);
  }
}

TEST(Se3Test, ExpRotationIsExpSO3) {
  testing::TestRandom random(24);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d omega =
        random.Uniform(0.0, kSe3Pi) * random.UnitVector();
    const Eigen::Vector3d rho = random.NormalVector(3.0);
    const Rigid3d T = ExpSE3(Twist(rho, omega));
    const Eigen::Quaterniond expected(
        Eigen::AngleAxisd(omega.norm(), omega.normalized()));
    EXPECT_LT(Se3RotationDistance(T.q, expected), 1e-15);
    EXPECT_LT((T.t - LeftJacobianBySeries(omega) * rho).norm(),
              1e-14 * (1.0 + rho.norm()));
  }
}

TEST(Se3Test, ExpIsAScrewMotionAboutItsAxis) {
  // A twist with rho = p x w + d w/|w| rotates by |w| about the line through
  // p along w and slides d along it: p maps to p + d w/|w|, and the point at
  // p + s w/|w| maps to p + (s + d) w/|w|.
  testing::TestRandom random(25);
  for (int i = 0; i < 500; ++i) {
    const double angle = random.Uniform(1e-3, kSe3Pi);
    const Eigen::Vector3d axis = random.UnitVector();
    const Eigen::Vector3d omega = angle * axis;
    const Eigen::Vector3d p = random.NormalVector(2.0);
    const double d = random.Uniform(-2.0, 2.0);
    // For a screw of pitch d / angle: rho = -w x p + (d / angle) w.
    const Eigen::Vector3d rho = -omega.cross(p) + (d / angle) * omega;
    const Rigid3d T = ExpSE3(Twist(rho, omega));
    const double s = random.Uniform(-3.0, 3.0);
    const Eigen::Vector3d on_axis = p + s * axis;
    EXPECT_LT((T * on_axis - (on_axis + d * axis)).norm(), 1e-13);
    // A point off the axis keeps its distance to the axis.
    const Eigen::Vector3d off = p + random.NormalVector(1.0);
    const Eigen::Vector3d moved = T * off;
    const auto distance_to_axis = [&](const Eigen::Vector3d& x) {
      return (x - p).cross(axis).norm();
    };
    EXPECT_NEAR(distance_to_axis(moved), distance_to_axis(off), 1e-13);
  }
}

TEST(Se3Test, ExpOfPureTranslationIsExact) {
  const Eigen::Vector3d rho(1.5, -2.25, 3.0);
  const Rigid3d T = ExpSE3(Twist(rho, Eigen::Vector3d::Zero()));
  EXPECT_EQ(T.q.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(T.t, rho);
}

TEST(Se3Test, LogOfPureTranslationIsTranslationAndZero) {
  testing::TestRandom random(26);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d t = random.NormalVector(5.0);
    const Vector6d xi = LogSE3(Rigid3d(Eigen::Quaterniond::Identity(), t));
    EXPECT_EQ(xi, Twist(t, Eigen::Vector3d::Zero()));
  }
}

TEST(Se3Test, LogOfIdentityIsZero) {
  EXPECT_EQ(LogSE3(Rigid3d::Identity()), Vector6d::Zero());
}

TEST(Se3Test, LogOfExpIsIdentityOnRandomInputs) {
  testing::TestRandom random(27);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d omega =
        random.Uniform(0.0, kSe3Pi) * random.UnitVector();
    const Eigen::Vector3d rho = random.NormalVector(3.0);
    const Vector6d xi = Twist(rho, omega);
    const Vector6d back = LogSE3(ExpSE3(xi));
    EXPECT_LT((back.tail<3>() - omega).norm(), 2e-15)
        << "angle " << omega.norm();
    EXPECT_LT((back.head<3>() - rho).norm(), 1e-14 * (1.0 + rho.norm()))
        << "angle " << omega.norm();
  }
}

TEST(Se3Test, ExpOfLogIsIdentityOnRandomInputs) {
  testing::TestRandom random(28);
  for (int i = 0; i < 2000; ++i) {
    const Rigid3d T(random.Rotation(), random.NormalVector(3.0));
    const Vector6d xi = LogSE3(T);
    EXPECT_LE(xi.tail<3>().norm(), kSe3Pi);
    const Rigid3d back = ExpSE3(xi);
    EXPECT_LT(Se3RotationDistance(back.q, T.q), 1e-15);
    EXPECT_LT((back.t - T.t).norm(), 1e-14 * (1.0 + T.t.norm()));
  }
}

TEST(Se3Test, LogIsTheSameForBothSignsOfTheQuaternion) {
  testing::TestRandom random(29);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Quaterniond q = random.Rotation();
    const Eigen::Vector3d t = random.NormalVector(2.0);
    const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_EQ(LogSE3(Rigid3d(q, t)), LogSE3(Rigid3d(minus_q, t)));
  }
}

TEST(Se3Test, RoundTripsAtEdgeAngles) {
  testing::TestRandom random(30);
  for (const double angle : Se3EdgeAngles()) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d omega = angle * random.UnitVector();
      const Eigen::Vector3d rho = random.NormalVector(2.0);
      const Vector6d xi = Twist(rho, omega);
      const Rigid3d T = ExpSE3(xi);
      const Vector6d back = LogSE3(T);
      // exp(log(T)) == T always, pi included.
      const Rigid3d T_back = ExpSE3(back);
      EXPECT_LT(Se3RotationDistance(T_back.q, T.q), 1e-15) << "angle " << angle;
      EXPECT_LT((T_back.t - T.t).norm(), 1e-13 * (1.0 + T.t.norm()))
          << "angle " << angle;
      if (angle < kSe3Pi) {
        // V is invertible up to and including pi (|V^-1| <= pi / 2), so rho
        // round-trips as well as omega does.
        EXPECT_LT((back - xi).norm(), 1e-14 * (1.0 + rho.norm()))
            << "angle " << angle;
      } else {
        // At pi, +-omega are both logarithms (and give different rho).
        EXPECT_NEAR(back.tail<3>().norm(), kSe3Pi, 1e-15);
        EXPECT_LT(back.tail<3>().normalized().cross(omega.normalized()).norm(),
                  1e-15);
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Derivatives through ceres::Jet. The Rigid3 is flattened as
// [q.x, q.y, q.z, q.w, t.x, t.y, t.z].

struct ExpSE3Flat {
  template <typename T>
  Eigen::Matrix<T, 7, 1> operator()(const Eigen::Matrix<T, 6, 1>& xi) const {
    const Rigid3<T> pose = ExpSE3(Vector6<T>(xi));
    Eigen::Matrix<T, 7, 1> out;
    out << pose.q.coeffs(), pose.t;
    return out;
  }
};

struct LogSE3OfFlat {
  template <typename T>
  Eigen::Matrix<T, 6, 1> operator()(const Eigen::Matrix<T, 7, 1>& x) const {
    const Eigen::Quaternion<T> q(x(3), x(0), x(1), x(2));
    return LogSE3(Rigid3<T>(q, x.template tail<3>()));
  }
};

Vector7d Flatten(const Rigid3d& T) {
  Vector7d x;
  x << T.q.coeffs(), T.t;
  return x;
}

TEST(Se3Test, ExpJetDerivativesMatchNumeric) {
  testing::TestRandom random(31);
  for (int i = 0; i < 200; ++i) {
    const Vector6d xi = Twist(random.NormalVector(2.0),
                              random.Uniform(0.0, 3.0) * random.UnitVector());
    EXPECT_TRUE(testing::JetMatchesNumeric(ExpSE3Flat(), xi, 1e-8));
  }
  for (const double angle : Se3EdgeAngles()) {
    for (int i = 0; i < 5; ++i) {
      const Vector6d xi =
          Twist(random.NormalVector(2.0), angle * random.UnitVector());
      EXPECT_TRUE(testing::JetMatchesNumeric(ExpSE3Flat(), xi, 1e-8))
          << "angle " << angle;
    }
  }
}

TEST(Se3Test, ExpJacobianAtZeroRotation) {
  // At omega = 0: dq/drho = 0, dq.vec/domega = I/2, dt/drho = I and
  // dt/domega = -Hat(rho)/2 (t = rho + (omega x rho)/2 + O(|omega|^2)).
  const Eigen::Vector3d rho(0.5, -1.0, 2.0);
  const Eigen::Matrix<double, 7, 6> J =
      testing::JetJacobian(ExpSE3Flat(), Twist(rho, Eigen::Vector3d::Zero()));
  Eigen::Matrix<double, 7, 6> expected = Eigen::Matrix<double, 7, 6>::Zero();
  expected.block<3, 3>(0, 3) = 0.5 * Eigen::Matrix3d::Identity();
  expected.block<3, 3>(4, 0) = Eigen::Matrix3d::Identity();
  expected.block<3, 3>(4, 3) = -0.5 * Hat(rho);
  EXPECT_EQ(J, expected);
}

TEST(Se3Test, LogJetDerivativesMatchNumeric) {
  testing::TestRandom random(32);
  for (int i = 0; i < 200; ++i) {
    const Rigid3d T(random.Rotation(), random.NormalVector(2.0));
    // Away from w = 0, where the sign flip is discontinuous in the raw
    // coefficients.
    if (std::abs(T.q.w()) < 1e-2) continue;
    EXPECT_TRUE(testing::JetMatchesNumeric(LogSE3OfFlat(), Flatten(T), 1e-7));
  }
  for (const double angle : Se3EdgeAngles()) {
    if (angle > 3.0) continue;
    for (int i = 0; i < 5; ++i) {
      const Rigid3d T(random.RotationOfAngle(angle), random.NormalVector(2.0));
      EXPECT_TRUE(testing::JetMatchesNumeric(LogSE3OfFlat(), Flatten(T), 1e-7))
          << "angle " << angle;
    }
  }
  for (const double angle : {kSe3Pi - 1e-2, kSe3Pi - 1e-4}) {
    const Rigid3d T(random.RotationOfAngle(angle), random.NormalVector(2.0));
    EXPECT_TRUE(
        testing::JetMatchesNumeric(LogSE3OfFlat(), Flatten(T), 1e-6, 1e-8))
        << "angle " << angle;
  }
}

TEST(Se3Test, LogJacobianAtIdentity) {
  // At the identity with t = 0: d omega / d q.vec = 2 I, d rho / d t = I.
  const Eigen::Matrix<double, 6, 7> J =
      testing::JetJacobian(LogSE3OfFlat(), Flatten(Rigid3d::Identity()));
  Eigen::Matrix<double, 6, 7> expected = Eigen::Matrix<double, 6, 7>::Zero();
  expected.block<3, 3>(0, 4) = Eigen::Matrix3d::Identity();
  expected.block<3, 3>(3, 0) = 2.0 * Eigen::Matrix3d::Identity();
  EXPECT_EQ(J, expected);
}

TEST(Se3Test, LogJacobianInvertsExpJacobian) {
  testing::TestRandom random(33);
  for (int i = 0; i < 100; ++i) {
    const Vector6d xi = Twist(random.NormalVector(2.0),
                              random.Uniform(0.0, 3.0) * random.UnitVector());
    const Eigen::Matrix<double, 7, 6> d_exp =
        testing::JetJacobian(ExpSE3Flat(), xi);
    const Eigen::Matrix<double, 6, 7> d_log =
        testing::JetJacobian(LogSE3OfFlat(), Flatten(ExpSE3(xi)));
    EXPECT_LT((d_log * d_exp - Eigen::Matrix<double, 6, 6>::Identity()).norm(),
              1e-11);
  }
}

}  // namespace
}  // namespace symba
