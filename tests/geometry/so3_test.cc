#include "symba/geometry/so3.h"

#include <gtest/gtest.h>

#include "test_support/random.h"

namespace symba {
namespace {

TEST(So3Test, ExpMatchesEigenAngleAxisOnRandomInputs) {
  testing::TestRandom random(1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d axis = random.UnitVector();
    const double angle = random.Uniform(0.0, 3.14159265358979323846);
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    const Eigen::Quaterniond actual = ExpSO3(Eigen::Vector3d(angle * axis));
    EXPECT_LT(expected.angularDistance(actual), 1e-12) << "angle " << angle;
  }
}

}  // namespace
}  // namespace symba
