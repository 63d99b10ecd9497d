#include "symba/factors/line_of_sight_rows.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "factors/factor_test_util.h"
#include "symba/factors/asymmetric_object_edge.h"
#include "test_support/random.h"

namespace symba {
namespace {

std::unique_ptr<ceres::CostFunction> TwoHypothesisEdge(const Rigid3d& T_co,
                                                       double sigma_t,
                                                       double sigma_r) {
  const Matrix6d sqrt_info = IsotropicPoseSqrtInfo(sigma_t, sigma_r);
  std::vector<PoseComponent> components = {
      {T_co, sqrt_info, 1.0},
      {Rigid3d(T_co.q * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()),
               T_co.t),
       sqrt_info,
       1.0}};
  std::unique_ptr<AsymmetricObjectEdge> edge;
  EXPECT_TRUE(
      CreateAsymmetricObjectEdge(components, MixtureOptions{}, &edge).ok());
  return edge;
}

// Rows of 2 m along and 5 cm across the sight line to t_co, the camera at
// the world origin with the identity rotation.
LineOfSightRows RowsFromTheOrigin(const Eigen::Vector3d& t_co) {
  return LineOfSightRows(
      TwoHypothesisEdge(Rigid3d(Eigen::Quaterniond::Identity(), t_co), 1, 1),
      3,
      t_co,
      2.0,
      0.05,
      Eigen::Quaterniond::Identity(),
      Eigen::Vector3d::Zero());
}

// The camera at the world origin looking along world z; the detection 2 m
// ahead, at (0, 0, 2): its line of sight is z.
TEST(LineOfSightRowsTest, RowsWeighAlongAndAcrossTheSightLine) {
  const Rigid3d T_wc;  // identity
  const Eigen::Vector3d t_co(0.0, 0.0, 2.0);
  LineOfSightRows rows(
      TwoHypothesisEdge(
          Rigid3d(Eigen::Quaterniond::Identity(), t_co), 2.0, 3.0),
      3,
      t_co,
      /*sigma_along=*/2.0,
      /*sigma_across=*/0.05,
      T_wc.q,
      T_wc.t);
  ASSERT_EQ(rows.num_residuals(), 7 + 3);
  testing::PoseBlocks camera(T_wc);
  // The object 0.1 m across (x) and 0.4 m along (z) from the detection.
  testing::PoseBlocks object(
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0.0, 2.4)));
  const std::vector<double*> parameters = {
      camera.q, camera.t, object.q, object.t};
  const testing::Evaluation e =
      testing::EvaluateWithJacobians(rows, parameters);
  ASSERT_TRUE(e.ok);
  // 0.1 / 0.05 = 2 across, 0.4 / 2 = 0.2 along.
  EXPECT_NEAR(e.residuals(7), 2.0, 1e-12);
  EXPECT_NEAR(e.residuals(8), 0.0, 1e-12);
  EXPECT_NEAR(e.residuals(9), 0.2, 1e-12);
  // Only the object's position moves the rows: S = diag(20, 20, 0.5).
  for (int b = 0; b < 3; ++b) {
    EXPECT_EQ(e.jacobians[b].bottomRows(3).cwiseAbs().maxCoeff(), 0.0) << b;
  }
  Eigen::Matrix3d expected = Eigen::Vector3d(20.0, 20.0, 0.5).asDiagonal();
  EXPECT_TRUE(e.jacobians[3].bottomRows(3).isApprox(expected, 1e-12));
  // The wrapped edge's rows are its own.
  std::unique_ptr<ceres::CostFunction> alone = TwoHypothesisEdge(
      Rigid3d(Eigen::Quaterniond::Identity(), t_co), 2.0, 3.0);
  const testing::Evaluation inner =
      testing::EvaluateWithJacobians(*alone, parameters);
  ASSERT_TRUE(inner.ok);
  EXPECT_EQ(e.residuals.head(7), inner.residuals);
  for (int b = 0; b < 4; ++b) {
    EXPECT_EQ(e.jacobians[b].topRows(7), inner.jacobians[b]) << b;
  }
}

TEST(LineOfSightRowsTest, OnlyTheAskedJacobiansAreWritten) {
  const Eigen::Vector3d t_co(0.1, -0.2, 2.0);
  LineOfSightRows rows = RowsFromTheOrigin(t_co);
  testing::PoseBlocks camera((Rigid3d()));
  testing::PoseBlocks object(Rigid3d(Eigen::Quaterniond::Identity(),
                                     Eigen::Vector3d(0.15, -0.2, 2.3)));
  const std::vector<double*> parameters = {
      camera.q, camera.t, object.q, object.t};
  const testing::Evaluation all =
      testing::EvaluateWithJacobians(rows, parameters);
  ASSERT_TRUE(all.ok);
  // The object's position only; the other pointers null.
  Eigen::Matrix<double, 10, 3, Eigen::RowMajor> position;
  position.setConstant(-7.0);
  double* jacobians[] = {nullptr, nullptr, nullptr, position.data()};
  Eigen::Matrix<double, 10, 1> residuals;
  ASSERT_TRUE(rows.Evaluate(parameters.data(), residuals.data(), jacobians));
  EXPECT_EQ(residuals, all.residuals);
  EXPECT_EQ(Eigen::MatrixXd(position), Eigen::MatrixXd(all.jacobians[3]));
}

TEST(LineOfSightRowsTest, RefreshMovesTheHeldCameraAndItsSightLine) {
  const Eigen::Vector3d t_co(0.0, 0.0, 2.0);
  LineOfSightRows rows = RowsFromTheOrigin(t_co);
  EXPECT_TRUE(rows.world_position().isApprox(Eigen::Vector3d(0, 0, 2)));
  // Turned by 90 degrees about y and moved by (1, 0, 0): the sight line is
  // now world x, the detection at (3, 0, 0).
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(M_PI / 2.0, Eigen::Vector3d::UnitY()));
  rows.Refresh(q, Eigen::Vector3d(1.0, 0.0, 0.0));
  EXPECT_TRUE(rows.world_position().isApprox(Eigen::Vector3d(3, 0, 0), 1e-12));
  const Eigen::Matrix3d expected =
      Eigen::Vector3d(0.5, 20.0, 20.0).asDiagonal();
  EXPECT_TRUE(rows.sqrt_information().isApprox(expected, 1e-12));
}

TEST(LineOfSightRowsTest, GradientCheckerPassesAt100RandomStates) {
  testing::TestRandom random(83);
  ceres::EigenQuaternionManifold quaternion;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion, nullptr, &quaternion, nullptr};
  for (int trial = 0; trial < 100; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Rigid3d T_co(random.Rotation(),
                       Eigen::Vector3d(random.Uniform(-0.5, 0.5),
                                       random.Uniform(-0.5, 0.5),
                                       random.Uniform(0.5, 4.0)));
    const Rigid3d T_wo = T_wc * T_co;
    testing::PoseBlocks camera(
        Rigid3d(T_wc.q, T_wc.t + random.NormalVector(0.05)));
    testing::PoseBlocks object(
        Rigid3d(T_wo.q, T_wo.t + random.NormalVector(0.05)));
    LineOfSightRows rows(TwoHypothesisEdge(T_co, 0.1, 0.1),
                         3,
                         T_co.t,
                         random.Uniform(0.5, 2.0),
                         random.Uniform(0.01, 0.1),
                         T_wc.q,
                         T_wc.t);
    std::string message;
    EXPECT_TRUE(
        testing::GradientIsCorrect(rows,
                                   manifolds,
                                   {camera.q, camera.t, object.q, object.t},
                                   1e-6,
                                   &message))
        << "trial " << trial << "\n"
        << message;
  }
}

TEST(LineOfSightRowsTest, AMixturesWinnerMarginIsTheWrappedEdges) {
  const Rigid3d T_co(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 2));
  std::unique_ptr<ceres::CostFunction> alone =
      TwoHypothesisEdge(T_co, 0.1, 0.1);
  LineOfSightRows rows(TwoHypothesisEdge(T_co, 0.1, 0.1),
                       3,
                       T_co.t,
                       2.0,
                       0.05,
                       Eigen::Quaterniond::Identity(),
                       Eigen::Vector3d::Zero());
  testing::PoseBlocks camera((Rigid3d()));
  testing::PoseBlocks object(Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())),
      T_co.t));
  const double* parameters[] = {camera.q, camera.t, object.q, object.t};
  double margin = 0.0;
  double expected = 0.0;
  bool null_won = true;
  bool expected_null = true;
  ASSERT_TRUE(rows.WinnerMargin(parameters, 5.0, &margin, &null_won));
  ASSERT_TRUE(dynamic_cast<const MixtureWinnerMargin&>(*alone).WinnerMargin(
      parameters, 5.0, &expected, &expected_null));
  EXPECT_EQ(margin, expected);
  EXPECT_EQ(null_won, expected_null);
  EXPECT_TRUE(std::isfinite(margin));
}

}  // namespace
}  // namespace symba
