#include "symba/geometry/spherical_angles.h"

#include <cmath>

#include <gtest/gtest.h>

#include "symba/geometry/angle.h"
#include "test_support/jet_check.h"
#include "test_support/random.h"

namespace symba {
namespace {

void ExpectAngles(const Eigen::Vector3d& a,
                  double expected_phi,
                  double expected_psi) {
  const SphericalAngles<double> angles = SphericalFromUnitVector(a);
  EXPECT_EQ(angles.phi, expected_phi) << "a = " << a.transpose();
  EXPECT_EQ(angles.psi, expected_psi) << "a = " << a.transpose();
}

TEST(SphericalAnglesTest, RoundTripFromRandomUnitVectors) {
  testing::TestRandom random(71);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d a = random.UnitVector();
    const SphericalAngles<double> angles = SphericalFromUnitVector(a);
    EXPECT_GE(angles.phi, 0.0);
    EXPECT_LE(angles.phi, kPi);
    EXPECT_GT(angles.psi, -kPi);
    EXPECT_LE(angles.psi, kPi);
    EXPECT_LT((UnitVectorFromSpherical(angles.phi, angles.psi) - a).norm(),
              1e-15);
  }
}

TEST(SphericalAnglesTest, RoundTripFromRandomAngles) {
  testing::TestRandom random(72);
  for (int i = 0; i < 2000; ++i) {
    // Away from the poles, where psi is undefined.
    const double phi = random.Uniform(1e-3, kPi - 1e-3);
    const double psi = random.Uniform(-kPi, kPi);
    const Eigen::Vector3d a = UnitVectorFromSpherical(phi, psi);
    EXPECT_NEAR(a.norm(), 1.0, 1e-15);
    const SphericalAngles<double> angles = SphericalFromUnitVector(a);
    EXPECT_NEAR(angles.phi, phi, 1e-15);
    EXPECT_NEAR(angles.psi, psi, 1e-12);
  }
}

TEST(SphericalAnglesTest, PolesAreExact) {
  ExpectAngles(Eigen::Vector3d(0.0, 0.0, 1.0), 0.0, 0.0);
  ExpectAngles(Eigen::Vector3d(0.0, 0.0, -1.0), kPi, 0.0);
  // Any length, and signed zeros in x and y.
  ExpectAngles(Eigen::Vector3d(0.0, 0.0, 5.0), 0.0, 0.0);
  ExpectAngles(Eigen::Vector3d(-0.0, -0.0, 0.5), 0.0, 0.0);
  ExpectAngles(Eigen::Vector3d(-0.0, 0.0, -2.0), kPi, 0.0);
  ExpectAngles(Eigen::Vector3d(0.0, -0.0, -1.0), kPi, 0.0);

  // f(0, psi) is +z for every psi, f(pi, psi) is -z to rounding.
  testing::TestRandom random(73);
  for (int i = 0; i < 100; ++i) {
    const double psi = random.Uniform(-kPi, kPi);
    EXPECT_EQ(UnitVectorFromSpherical(0.0, psi), Eigen::Vector3d::UnitZ());
    EXPECT_LT(
        (UnitVectorFromSpherical(kPi, psi) + Eigen::Vector3d::UnitZ()).norm(),
        2e-16);
    EXPECT_EQ(UnitVectorFromSpherical(kPi, psi).z(), -1.0);
  }
}

TEST(SphericalAnglesTest, EquatorIsExact) {
  ExpectAngles(Eigen::Vector3d(1.0, 0.0, 0.0), 0.5 * kPi, 0.0);
  ExpectAngles(Eigen::Vector3d(0.0, 1.0, 0.0), 0.5 * kPi, 0.5 * kPi);
  ExpectAngles(Eigen::Vector3d(0.0, -1.0, 0.0), 0.5 * kPi, -0.5 * kPi);
  ExpectAngles(Eigen::Vector3d(-1.0, 0.0, 0.0), 0.5 * kPi, kPi);
  // psi is in (-pi, pi]: the negative x axis is +pi with either zero sign.
  ExpectAngles(Eigen::Vector3d(-1.0, -0.0, 0.0), 0.5 * kPi, kPi);
  ExpectAngles(Eigen::Vector3d(-2.0, -0.0, -0.0), 0.5 * kPi, kPi);
  ExpectAngles(Eigen::Vector3d(1.0, 1.0, 0.0), 0.5 * kPi, 0.25 * kPi);
  ExpectAngles(Eigen::Vector3d(-3.0, -3.0, 0.0), 0.5 * kPi, -0.75 * kPi);
  ExpectAngles(Eigen::Vector3d(1.0, 0.0, -0.0), 0.5 * kPi, 0.0);

  testing::TestRandom random(74);
  for (int i = 0; i < 200; ++i) {
    const double psi = random.Uniform(-kPi, kPi);
    const Eigen::Vector3d a(std::cos(psi), std::sin(psi), 0.0);
    const SphericalAngles<double> angles = SphericalFromUnitVector(a);
    EXPECT_EQ(angles.phi, 0.5 * kPi);
    EXPECT_NEAR(angles.psi, psi, 1e-15);
    const Eigen::Vector3d back = UnitVectorFromSpherical(0.5 * kPi, psi);
    EXPECT_NEAR(back.z(), 0.0, 1e-16);
    EXPECT_LT((back - a).norm(), 1e-15);
  }
}

TEST(SphericalAnglesTest, NearThePolesTheRoundTripStillHolds) {
  testing::TestRandom random(75);
  for (const double phi : {1e-300, 1e-100, 1e-12, 1e-6}) {
    for (const double psi : {-3.0, -1.0, 0.0, 0.5, 2.5}) {
      for (const double pole : {0.0, kPi}) {
        const double polar = pole == 0.0 ? phi : kPi - phi;
        const Eigen::Vector3d a = UnitVectorFromSpherical(polar, psi);
        const SphericalAngles<double> angles = SphericalFromUnitVector(a);
        EXPECT_LT((UnitVectorFromSpherical(angles.phi, angles.psi) - a).norm(),
                  1e-15)
            << "phi " << polar << " psi " << psi;
      }
    }
  }
}

TEST(SphericalAnglesTest, PsiIsTheAzimuthFromXTowardY) {
  // A quarter turn about +z adds pi/2 to psi (right-handed about z).
  testing::TestRandom random(76);
  for (int i = 0; i < 200; ++i) {
    const double phi = random.Uniform(0.1, 3.0);
    const double psi = random.Uniform(-kPi, 0.5 * kPi);
    const Eigen::Vector3d a = UnitVectorFromSpherical(phi, psi);
    const Eigen::Vector3d turned(-a.y(), a.x(), a.z());
    EXPECT_NEAR(SphericalFromUnitVector(turned).psi, psi + 0.5 * kPi, 1e-14);
  }
}

struct UnitVectorOfAngles {
  template <typename T>
  Eigen::Matrix<T, 3, 1> operator()(const Eigen::Matrix<T, 2, 1>& x) const {
    return UnitVectorFromSpherical(x(0), x(1));
  }
};

struct AnglesOfVector {
  template <typename T>
  Eigen::Matrix<T, 2, 1> operator()(const Eigen::Matrix<T, 3, 1>& a) const {
    const SphericalAngles<T> angles = SphericalFromUnitVector(Vector3<T>(a));
    return Eigen::Matrix<T, 2, 1>(angles.phi, angles.psi);
  }
};

TEST(SphericalAnglesTest, UnitVectorJetDerivativesMatchNumeric) {
  testing::TestRandom random(77);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d x(random.Uniform(0.0, kPi),
                            random.Uniform(-kPi, kPi));
    EXPECT_TRUE(testing::JetMatchesNumeric(UnitVectorOfAngles(), x, 1e-8));
  }
  // Differentiable at the poles too: d f / d phi = [cos psi, sin psi, 0].
  for (const double psi : {-2.0, 0.0, 1.0}) {
    const Eigen::Vector2d x(0.0, psi);
    EXPECT_TRUE(testing::JetMatchesNumeric(UnitVectorOfAngles(), x, 1e-8));
    const Eigen::Matrix<double, 3, 2> J =
        testing::JetJacobian(UnitVectorOfAngles(), x);
    EXPECT_EQ(J(0, 0), std::cos(psi));
    EXPECT_EQ(J(1, 0), std::sin(psi));
    EXPECT_EQ(J.col(1), Eigen::Vector3d::Zero());
    EXPECT_TRUE(testing::JetMatchesNumeric(
        UnitVectorOfAngles(), Eigen::Vector2d(kPi, psi), 1e-8));
  }
}

TEST(SphericalAnglesTest, AnglesJetDerivativesMatchNumeric) {
  testing::TestRandom random(78);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d a = random.UnitVector();
    // Away from the poles (singular) and from the psi cut at -x.
    if (a.head<2>().norm() < 1e-2) continue;
    if (a.x() < 0.0 && std::abs(a.y()) < 1e-3) continue;
    EXPECT_TRUE(testing::JetMatchesNumeric(AnglesOfVector(), a, 1e-7));
  }
  // On the equator, and off the unit sphere.
  for (const Eigen::Vector3d& a : {Eigen::Vector3d(1.0, 0.0, 0.0),
                                   Eigen::Vector3d(0.0, -1.0, 0.0),
                                   Eigen::Vector3d(0.6, 0.8, 0.0),
                                   Eigen::Vector3d(2.0, -1.0, 3.0)}) {
    EXPECT_TRUE(testing::JetMatchesNumeric(AnglesOfVector(), a, 1e-7));
  }
  // At (1, 0, 0): d phi / d z = -1, d psi / d y = 1, the rest 0.
  const Eigen::Matrix<double, 2, 3> J = testing::JetJacobian(
      AnglesOfVector(), Eigen::Vector3d(Eigen::Vector3d::UnitX()));
  Eigen::Matrix<double, 2, 3> expected;
  expected << 0.0, 0.0, -1.0,  //
      0.0, 1.0, 0.0;
  EXPECT_EQ(J, expected);
}

}  // namespace
}  // namespace symba
