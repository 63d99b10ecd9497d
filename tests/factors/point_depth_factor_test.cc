#include "symba/factors/point_depth_factor.h"

#include <memory>
#include <string>
#include <vector>

#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "factors/factor_test_util.h"
#include "test_support/random.h"

namespace symba {
namespace {

TEST(PointDepthFactorTest, ZeroAtTheTrueDepthAndHandValue) {
  // Camera at (1, 0, 0) looking along world z; point at (1, 0.5, 3): depth 3.
  testing::PoseBlocks camera(
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0)));
  double p_w[3] = {1.0, 0.5, 3.0};
  std::unique_ptr<ceres::CostFunction> exact(
      PointDepthFactor::Create(3.0, 0.02));
  double* parameters[3] = {camera.q, camera.t, p_w};
  double residual = 1.0;
  ASSERT_TRUE(exact->Evaluate(parameters, &residual, nullptr));
  EXPECT_EQ(residual, 0.0);
  // Measured 2.9 m with sigma 0.02 m: (3 - 2.9) / 0.02 = 5.
  std::unique_ptr<ceres::CostFunction> off(PointDepthFactor::Create(2.9, 0.02));
  ASSERT_TRUE(off->Evaluate(parameters, &residual, nullptr));
  EXPECT_NEAR(residual, 5.0, 1e-12);
}

TEST(PointDepthFactorTest, GradientCheckerPassesAt200RandomStates) {
  testing::TestRandom random(61);
  ceres::EigenQuaternionManifold quaternion;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion, nullptr, nullptr};
  for (int trial = 0; trial < 200; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    testing::PoseBlocks camera(T_wc);
    const Eigen::Vector3d p_c(
        random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(0.5, 8.0));
    Eigen::Vector3d p = T_wc * p_c;
    double p_w[3] = {p.x(), p.y(), p.z()};
    std::unique_ptr<ceres::CostFunction> cost(PointDepthFactor::Create(
        p_c.z() + random.Normal(0.05), random.Uniform(0.005, 0.05)));
    std::string message;
    EXPECT_TRUE(testing::GradientIsCorrect(
        *cost, manifolds, {camera.q, camera.t, p_w}, 1e-6, &message))
        << "trial " << trial << "\n"
        << message;
  }
}

}  // namespace
}  // namespace symba
