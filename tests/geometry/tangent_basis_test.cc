#include "symba/geometry/tangent_basis.h"

#include <cmath>

#include <gtest/gtest.h>

#include "test_support/jet_check.h"
#include "test_support/random.h"

namespace symba {
namespace {

using Basis = Eigen::Matrix<double, 3, 2>;

// Orthonormal, perpendicular to x, and (b1, b2, x) right-handed, each to
// within `tolerance` (0 demands exact).
void ExpectTangentBasis(const Eigen::Vector3d& x, double tolerance) {
  const Basis B = TangentBasis(x);
  ASSERT_TRUE(B.allFinite()) << "x = " << x.transpose();
  const Eigen::Vector3d b1 = B.col(0);
  const Eigen::Vector3d b2 = B.col(1);
  EXPECT_LE((B.transpose() * B - Eigen::Matrix2d::Identity()).norm(), tolerance)
      << "x = " << x.transpose();
  EXPECT_LE((B.transpose() * x).norm(), tolerance) << "x = " << x.transpose();
  EXPECT_LE((b1.cross(b2) - x).norm(), tolerance) << "x = " << x.transpose();
  // The other two cyclic products of a right-handed frame.
  EXPECT_LE((b2.cross(x) - b1).norm(), tolerance) << "x = " << x.transpose();
  EXPECT_LE((x.cross(b1) - b2).norm(), tolerance) << "x = " << x.transpose();
}

TEST(TangentBasisTest, OrthonormalAndRightHandedAtRandomPoints) {
  testing::TestRandom random(81);
  for (int i = 0; i < 2000; ++i) {
    ExpectTangentBasis(random.UnitVector(), 1e-15);
  }
}

TEST(TangentBasisTest, PolesAreExact) {
  Basis north;
  north << 1.0, 0.0,  //
      0.0, 1.0,       //
      0.0, 0.0;
  EXPECT_EQ(TangentBasis(Eigen::Vector3d(0.0, 0.0, 1.0)), north);
  Basis south;
  south << 1.0, 0.0,  //
      0.0, -1.0,      //
      0.0, 0.0;
  EXPECT_EQ(TangentBasis(Eigen::Vector3d(0.0, 0.0, -1.0)), south);
  ExpectTangentBasis(Eigen::Vector3d(0.0, 0.0, 1.0), 0.0);
  ExpectTangentBasis(Eigen::Vector3d(0.0, 0.0, -1.0), 0.0);
  // Signed zeros change nothing.
  EXPECT_EQ(TangentBasis(Eigen::Vector3d(-0.0, -0.0, 1.0)), north);
  EXPECT_EQ(TangentBasis(Eigen::Vector3d(-0.0, 0.0, -1.0)), south);
}

TEST(TangentBasisTest, EquatorIsExact) {
  Basis at_x;        // x = e_x: b1 = -e_z, b2 = e_y
  at_x << 0.0, 0.0,  //
      0.0, 1.0,      //
      -1.0, 0.0;
  EXPECT_EQ(TangentBasis(Eigen::Vector3d(1.0, 0.0, 0.0)), at_x);
  Basis at_y;        // x = e_y: b1 = e_x, b2 = -e_z
  at_y << 1.0, 0.0,  //
      0.0, 0.0,      //
      0.0, -1.0;
  EXPECT_EQ(TangentBasis(Eigen::Vector3d(0.0, 1.0, 0.0)), at_y);
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(1.0, 0.0, 0.0),
                                   Eigen::Vector3d(-1.0, 0.0, 0.0),
                                   Eigen::Vector3d(0.0, 1.0, 0.0),
                                   Eigen::Vector3d(0.0, -1.0, 0.0),
                                   Eigen::Vector3d(0.6, 0.8, 0.0),
                                   Eigen::Vector3d(0.6, -0.8, -0.0)}) {
    ExpectTangentBasis(x, 1e-15);
  }
  testing::TestRandom random(82);
  for (int i = 0; i < 500; ++i) {
    const double psi = random.Uniform(-3.2, 3.2);
    ExpectTangentBasis(Eigen::Vector3d(std::cos(psi), std::sin(psi), 0.0),
                       1e-15);
  }
}

TEST(TangentBasisTest, NearTheEquatorFromBothSides) {
  testing::TestRandom random(83);
  for (const double z : {1e-300, 1e-17, 1e-12, 1e-8, 1e-4}) {
    for (const double sign : {1.0, -1.0}) {
      for (int i = 0; i < 50; ++i) {
        const double psi = random.Uniform(-3.2, 3.2);
        const double r = std::sqrt(1.0 - z * z);
        const Eigen::Vector3d x(r * std::cos(psi), r * std::sin(psi), sign * z);
        ExpectTangentBasis(x, 1e-15);
      }
    }
  }
}

TEST(TangentBasisTest, NearThePoles) {
  testing::TestRandom random(84);
  for (const double rho : {1e-300, 1e-100, 1e-12, 1e-8, 1e-4}) {
    for (const double sign : {1.0, -1.0}) {
      for (int i = 0; i < 50; ++i) {
        const double psi = random.Uniform(-3.2, 3.2);
        const Eigen::Vector3d x(rho * std::cos(psi),
                                rho * std::sin(psi),
                                sign * std::sqrt(1.0 - rho * rho));
        ExpectTangentBasis(x, 1e-15);
        // Continuous at the poles: close to the pole's own basis.
        const Basis at_pole = TangentBasis(Eigen::Vector3d(0.0, 0.0, sign));
        EXPECT_LT((TangentBasis(x) - at_pole).norm(), 2.0 * rho);
      }
    }
  }
}

struct TangentBasisFlat {
  // The 3 x 2 basis as a 6-vector, column-major.
  template <typename T>
  Eigen::Matrix<T, 6, 1> operator()(const Eigen::Matrix<T, 3, 1>& x) const {
    const Eigen::Matrix<T, 3, 2> B = TangentBasis(Vector3<T>(x));
    return Eigen::Map<const Eigen::Matrix<T, 6, 1>>(B.data());
  }
};

TEST(TangentBasisTest, JetDerivativesMatchNumeric) {
  testing::TestRandom random(85);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d x = random.UnitVector();
    // The branch switches at z = 0; the step must not cross it.
    if (std::abs(x.z()) < 1e-4) continue;
    EXPECT_TRUE(testing::JetMatchesNumeric(TangentBasisFlat(), x, 1e-7));
  }
  for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.0, 0.0, 1.0),
                                   Eigen::Vector3d(0.0, 0.0, -1.0),
                                   Eigen::Vector3d(0.6, 0.8, 1e-3),
                                   Eigen::Vector3d(0.6, 0.8, -1e-3)}) {
    EXPECT_TRUE(testing::JetMatchesNumeric(TangentBasisFlat(), x, 1e-7));
  }
  // On the equator itself, the one-sided (z >= 0) derivative: use a step
  // that stays on that side in z by checking the x and y columns only.
  const Eigen::Vector3d equator(0.6, 0.8, 0.0);
  const Eigen::Matrix<double, 6, 3> J_jet =
      testing::JetJacobian(TangentBasisFlat(), equator);
  const Eigen::Matrix<double, 6, 3> J_numeric =
      testing::NumericJacobian(TangentBasisFlat(), equator, 1e-6);
  EXPECT_LT((J_jet.leftCols<2>() - J_numeric.leftCols<2>()).norm(), 1e-8);
  EXPECT_TRUE(J_jet.allFinite());
}

}  // namespace
}  // namespace symba
