#include "symba/geometry/angle.h"

#include <cmath>
#include <limits>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "test_support/random.h"

namespace symba {
namespace {

TEST(AngleTest, ConstantsArePi) {
  EXPECT_EQ(kPi, std::acos(-1.0));
  EXPECT_EQ(kTwoPi, 2.0 * std::acos(-1.0));
}

TEST(AngleTest, WrapToPiExactValues) {
  EXPECT_EQ(WrapToPi(0.0), 0.0);
  EXPECT_EQ(WrapToPi(kPi), kPi);
  EXPECT_EQ(WrapToPi(-kPi), kPi);
  EXPECT_EQ(WrapToPi(kTwoPi), 0.0);
  EXPECT_EQ(WrapToPi(-kTwoPi), 0.0);
  // 3 * kPi, 5 * kPi and 7 * kPi are exact in double.
  EXPECT_EQ(WrapToPi(3.0 * kPi), kPi);
  EXPECT_EQ(WrapToPi(-3.0 * kPi), kPi);
  EXPECT_EQ(WrapToPi(5.0 * kPi), kPi);
  EXPECT_EQ(WrapToPi(-7.0 * kPi), kPi);
  EXPECT_EQ(WrapToPi(4.0 * kPi), 0.0);
  EXPECT_EQ(WrapToPi(0.5 * kPi), 0.5 * kPi);
  EXPECT_EQ(WrapToPi(-0.5 * kPi), -0.5 * kPi);
  EXPECT_EQ(WrapToPi(1.5 * kPi), -0.5 * kPi);
  EXPECT_EQ(WrapToPi(-1.5 * kPi), 0.5 * kPi);
  EXPECT_EQ(WrapToPi(1.0), 1.0);
  EXPECT_EQ(WrapToPi(-1.0), -1.0);
}

TEST(AngleTest, WrapToPiOfLargeMultiples) {
  // Exact powers of two times kPi stay exact, so these are exact.
  for (int e = 1; e <= 40; ++e) {
    const double even_multiple = std::ldexp(kPi, e);  // 2^e pi
    EXPECT_EQ(WrapToPi(even_multiple), 0.0) << "2^" << e << " pi";
    EXPECT_EQ(WrapToPi(-even_multiple), 0.0) << "-2^" << e << " pi";
  }
  // x + 2 pi k for large k: the result is x to the rounding of the input.
  for (const double k : {1.0, 7.0, 100.0, -100.0, 12345.0, -1e6, 1e8}) {
    for (const double x : {0.25, -3.0, 3.0, 1e-3}) {
      const double angle = x + k * kTwoPi;
      const double tolerance =
          8.0 * std::numeric_limits<double>::epsilon() * std::abs(angle);
      EXPECT_NEAR(WrapToPi(angle), x, tolerance) << "k " << k << " x " << x;
    }
  }
}

TEST(AngleTest, WrapToPiOfHugeInputsIsStillInRange) {
  // Past about 1e16 rad a product k * 2pi is off by more than pi; the
  // reduction must still land in (-pi, pi].
  for (const double angle : {3e16,
                             1e17,
                             1e18,
                             -1e18,
                             123456789.0e12,
                             1e20,
                             1e100,
                             1e300,
                             -1e300,
                             1.7e308,
                             -1.7e308,
                             std::numeric_limits<double>::max()}) {
    const double wrapped = WrapToPi(angle);
    EXPECT_GT(wrapped, -kPi) << angle;
    EXPECT_LE(wrapped, kPi) << angle;
  }
  // 2^e kPi is an exact multiple of kTwoPi for every e >= 1.
  for (int e = 41; e <= 1000; e += 7) {
    EXPECT_EQ(WrapToPi(std::ldexp(kPi, e)), 0.0) << "2^" << e << " pi";
  }
}

TEST(AngleTest, WrapToPiIsInRangeAndDiffersByMultipleOfTwoPi) {
  testing::TestRandom random(41);
  for (int i = 0; i < 5000; ++i) {
    const double angle = random.Uniform(-1e3, 1e3);
    const double wrapped = WrapToPi(angle);
    EXPECT_GT(wrapped, -kPi);
    EXPECT_LE(wrapped, kPi);
    const double turns = (angle - wrapped) / kTwoPi;
    EXPECT_NEAR(turns, std::round(turns), 1e-12) << angle;
  }
}

TEST(AngleTest, WrapToPiLeavesTheRangeUnchanged) {
  testing::TestRandom random(42);
  for (int i = 0; i < 5000; ++i) {
    const double angle = random.Uniform(-kPi, kPi);
    if (angle == -kPi) continue;
    EXPECT_EQ(WrapToPi(angle), angle);
  }
  // The largest double below pi, and the smallest above -pi.
  const double below_pi = std::nextafter(kPi, 0.0);
  const double above_minus_pi = std::nextafter(-kPi, 0.0);
  EXPECT_EQ(WrapToPi(below_pi), below_pi);
  EXPECT_EQ(WrapToPi(above_minus_pi), above_minus_pi);
  // Just past either end wraps to just inside the other end.
  const double above_pi = std::nextafter(kPi, 4.0);
  EXPECT_NEAR(WrapToPi(above_pi), -kPi, 1e-15);
  EXPECT_GT(WrapToPi(above_pi), -kPi);
  const double below_minus_pi = std::nextafter(-kPi, -4.0);
  EXPECT_NEAR(WrapToPi(below_minus_pi), kPi, 1e-15);
  EXPECT_LE(WrapToPi(below_minus_pi), kPi);
}

TEST(AngleTest, WrapToPiReturnsNonFiniteInputUnchanged) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(WrapToPi(inf), inf);
  EXPECT_EQ(WrapToPi(-inf), -inf);
  EXPECT_TRUE(std::isnan(WrapToPi(std::numeric_limits<double>::quiet_NaN())));
  using Jet = ceres::Jet<double, 1>;
  const Jet wrapped_inf = WrapToPi(Jet(inf, 0));
  EXPECT_EQ(wrapped_inf.a, inf);
  EXPECT_EQ(wrapped_inf.v(0), 1.0);
}

TEST(AngleTest, WrapToPiPassesJetDerivativesThrough) {
  using Jet = ceres::Jet<double, 2>;
  for (const double angle :
       {0.3, 3.0 * kPi + 0.5, -7.0 * kPi - 0.5, -kPi, 1e6 + 0.1, 1e18}) {
    Jet x(angle, 0);
    x.v(1) = -2.5;
    const Jet wrapped = WrapToPi(x);
    EXPECT_EQ(wrapped.a, WrapToPi(angle));  // bit for bit
    EXPECT_EQ(wrapped.v(0), 1.0);
    EXPECT_EQ(wrapped.v(1), -2.5);
  }
}

TEST(AngleTest, CircularDistanceExactValues) {
  EXPECT_EQ(CircularDistance(0.0, 0.0), 0.0);
  EXPECT_EQ(CircularDistance(1.0, 1.0), 0.0);
  EXPECT_EQ(CircularDistance(0.0, kPi), kPi);
  EXPECT_EQ(CircularDistance(kPi, 0.0), kPi);
  EXPECT_EQ(CircularDistance(0.25, -0.25), 0.5);
  EXPECT_EQ(CircularDistance(0.0, kTwoPi), 0.0);
  EXPECT_NEAR(CircularDistance(kPi - 0.1, -kPi + 0.1), 0.2, 1e-15);
  EXPECT_NEAR(CircularDistance(0.1, kTwoPi - 0.1), 0.2, 1e-15);
}

TEST(AngleTest, CircularDistanceIsASymmetricDistanceInZeroPi) {
  testing::TestRandom random(43);
  for (int i = 0; i < 2000; ++i) {
    const double a = random.Uniform(-20.0, 20.0);
    const double b = random.Uniform(-20.0, 20.0);
    const double d = CircularDistance(a, b);
    EXPECT_GE(d, 0.0);
    EXPECT_LE(d, kPi);
    EXPECT_NEAR(d, CircularDistance(b, a), 1e-13);
    // The chord between the two points on the unit circle is 2 sin(d / 2).
    const double chord =
        std::hypot(std::cos(a) - std::cos(b), std::sin(a) - std::sin(b));
    EXPECT_NEAR(2.0 * std::sin(0.5 * d), chord, 1e-12);
  }
}

}  // namespace
}  // namespace symba
