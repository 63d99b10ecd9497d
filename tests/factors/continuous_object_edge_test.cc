#include "symba/factors/continuous_object_edge.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "factors/factor_test_util.h"
#include "symba/geometry/swing_twist.h"
#include "symba/geometry/tangent_basis.h"
#include "symba/manifolds/axis_manifold.h"
#include "test_support/random.h"

namespace symba {
namespace {

using testing::PoseBlocks;

std::unique_ptr<ContinuousObjectEdge> MakeEdge(
    std::vector<TranslationComponent> components, const AxisMeasurement& axis) {
  std::unique_ptr<ContinuousObjectEdge> edge;
  const Status status = CreateContinuousObjectEdge(
      std::move(components), axis, MixtureOptions(), &edge);
  EXPECT_TRUE(status.ok()) << status.message();
  return edge;
}

struct ContinuousState {
  PoseBlocks camera;
  double t_wo[3];
  double a_w[3];
  ContinuousState(const Rigid3d& T_wc,
                  const Eigen::Vector3d& position,
                  const Eigen::Vector3d& axis)
      : camera(T_wc) {
    Eigen::Map<Eigen::Vector3d> t_map(t_wo);
    Eigen::Map<Eigen::Vector3d> a_map(a_w);
    t_map = position;
    a_map = axis.normalized();
  }
  std::vector<double*> Parameters() { return {camera.q, camera.t, t_wo, a_w}; }
};

AxisMeasurement Axis(const Eigen::Vector3d& a_c, double sigma, double gamma) {
  AxisMeasurement axis;
  axis.a_c = a_c.normalized();
  axis.sqrt_info = Eigen::Matrix2d::Identity() / sigma;
  axis.gamma = gamma;
  return axis;
}

TEST(ContinuousObjectEdgeTest, ZeroResidualAtTheTrueState) {
  testing::TestRandom random(31);
  for (int trial = 0; trial < 20; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Eigen::Vector3d t_wo = random.NormalVector(2.0);
    const Eigen::Vector3d a_w = random.UnitVector();
    const Eigen::Vector3d t_co = T_wc.Inverse() * t_wo;
    const Eigen::Vector3d a_c = T_wc.q.conjugate() * a_w;
    auto edge = MakeEdge({{t_co, Eigen::Matrix3d::Identity() / 0.05, 1.0}},
                         Axis(a_c, 0.1, 1.0));
    ContinuousState state(T_wc, t_wo, a_w);
    const auto e = testing::EvaluateWithJacobians(*edge, state.Parameters());
    ASSERT_TRUE(e.ok);
    EXPECT_LT(e.residuals.norm(), 1e-12);
  }
}

TEST(ContinuousObjectEdgeTest, HandComputedTranslationAndAxisErrors) {
  // Camera at the origin; hypothesis 2 m ahead; measured axis z (camera).
  // Object 0.1 m to the right: r_t = (0 - 0.1) / 0.05 = -2 on x.
  // World axis tilted 0.2 rad about x: on the tangent plane at z (basis
  // (x, y) there) it sits at (0, -0.2) rad; r_axis = gamma / sigma * that
  // = 2 / 0.1 * (0, -0.2) = (0, -4).
  auto edge = MakeEdge(
      {{Eigen::Vector3d(0, 0, 2), Eigen::Matrix3d::Identity() / 0.05, 1.0}},
      Axis(Eigen::Vector3d::UnitZ(), 0.1, 2.0));
  const Eigen::Vector3d a_w = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()) *
                              Eigen::Vector3d::UnitZ();
  ContinuousState state(Rigid3d::Identity(), Eigen::Vector3d(0.1, 0, 2), a_w);
  const auto e = testing::EvaluateWithJacobians(*edge, state.Parameters());
  ASSERT_TRUE(e.ok);
  Eigen::Matrix<double, 6, 1> expected;
  expected << -2.0, 0, 0, 0, -4.0, 0;
  EXPECT_LT((e.residuals - expected).norm(), 1e-12) << e.residuals.transpose();
}

// 240 random states; every third has a vertical world axis, every fifth a
// world axis within 1e-7 rad of the measurement (the series branch of the
// sphere logarithm), and up to 6 translation hypotheses.
TEST(ContinuousObjectEdgeTest, GradientCheckerPassesAt240RandomStates) {
  testing::TestRandom random(32);
  ceres::EigenQuaternionManifold quaternion;
  AxisManifold axis_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion, nullptr, nullptr, &axis_manifold};
  for (int trial = 0; trial < 240; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Eigen::Vector3d t_wo = T_wc * Eigen::Vector3d(0, 0, 2.5);
    Eigen::Vector3d a_w =
        trial % 3 == 0 ? Eigen::Vector3d::UnitZ() : random.UnitVector();
    Eigen::Vector3d a_c_true = T_wc.q.conjugate() * a_w;
    Eigen::Vector3d a_c =
        (trial % 5 == 0)
            ? Eigen::Vector3d(Eigen::AngleAxisd(1e-7, random.UnitVector()) *
                              a_c_true)
            : Eigen::Vector3d(Eigen::AngleAxisd(random.Uniform(0, 1.0),
                                                random.UnitVector()) *
                              a_c_true);
    std::vector<TranslationComponent> components;
    const int n = 1 + trial % 6;
    for (int j = 0; j < n; ++j) {
      components.push_back(
          {T_wc.Inverse() * t_wo + random.NormalVector(0.2),
           Eigen::Matrix3d::Identity() / random.Uniform(0.02, 0.2),
           random.Uniform(0.1, 1.0)});
    }
    auto edge = MakeEdge(
        components,
        Axis(a_c, random.Uniform(0.05, 0.3), random.Uniform(0.5, 3.0)));
    ContinuousState state(T_wc, t_wo, a_w);
    std::string message;
    EXPECT_TRUE(testing::GradientIsCorrect(
        *edge, manifolds, state.Parameters(), 1e-6, &message))
        << "trial " << trial << "\n"
        << message;
  }
}

// Two translation hypotheses 1 m apart along x with weights 0.6 / 0.4 and
// unit information: the winner switches at x* = 0.5 + log(0.6 / 0.4); the
// axis rows do not depend on the winner.
TEST(ContinuousObjectEdgeTest, WinnerSwitchesOnTranslationOnly) {
  const AxisMeasurement axis = Axis(Eigen::Vector3d::UnitZ(), 0.1, 1.0);
  auto edge =
      MakeEdge({{Eigen::Vector3d(0, 0, 2), Eigen::Matrix3d::Identity(), 0.6},
                {Eigen::Vector3d(1, 0, 2), Eigen::Matrix3d::Identity(), 0.4}},
               axis);
  auto only1 = MakeEdge(
      {{Eigen::Vector3d(1, 0, 2), Eigen::Matrix3d::Identity(), 1.0}}, axis);
  const double x_switch = 0.5 + std::log(0.6 / 0.4);
  const Eigen::Vector3d a_w = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                              Eigen::Vector3d::UnitZ();
  MixtureSelection selection;
  ContinuousState before(
      Rigid3d::Identity(), Eigen::Vector3d(x_switch - 1e-7, 0, 2), a_w);
  ASSERT_TRUE(edge->Select(before.Parameters().data(), &selection));
  EXPECT_EQ(selection.component, 0);
  ContinuousState after(
      Rigid3d::Identity(), Eigen::Vector3d(x_switch + 1e-7, 0, 2), a_w);
  ASSERT_TRUE(edge->Select(after.Parameters().data(), &selection));
  EXPECT_EQ(selection.component, 1);
  const auto mixed_before =
      testing::EvaluateWithJacobians(*edge, before.Parameters());
  const auto mixed = testing::EvaluateWithJacobians(*edge, after.Parameters());
  const auto single =
      testing::EvaluateWithJacobians(*only1, after.Parameters());
  ASSERT_TRUE(mixed_before.ok && mixed.ok && single.ok);
  EXPECT_LT((mixed.residuals.head<5>() - single.residuals.head<5>()).norm(),
            1e-12);
  for (int b = 0; b < 4; ++b) {
    EXPECT_LT(
        (mixed.jacobians[b].topRows(5) - single.jacobians[b].topRows(5)).norm(),
        1e-12);
  }
  // Axis rows: (0.3 rad about y seen from z) = (0.3, 0) * 10, on both sides.
  EXPECT_NEAR(mixed.residuals(3), 3.0, 1e-12);
  EXPECT_NEAR(mixed.residuals(4), 0.0, 1e-12);
  EXPECT_LT(
      (mixed.residuals.segment<2>(3) - mixed_before.residuals.segment<2>(3))
          .norm(),
      1e-6);
  EXPECT_NEAR(mixed.residuals(5), std::sqrt(2.0 * std::log(0.6 / 0.4)), 1e-12);
}

// The hand-written winner (ContinuousComponentCost) against autodiff of the
// templated residual it implements, in the ambient coordinates of every
// block, at 200 random states: quaternions and axes off the unit sphere by up
// to 10 %, every fourth state with the predicted axis within 1e-6 rad of the
// measurement (the series branch of SphereLog), every seventh with it more
// than 90 degrees away (c < 0).
TEST(ContinuousObjectEdgeTest, HandWrittenJacobianEqualsAutoDiff) {
  testing::TestRandom random(33);
  for (int trial = 0; trial < 200; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Eigen::Vector3d t_wo = T_wc * Eigen::Vector3d(0, 0, 2.5);
    const Eigen::Vector3d a_w = random.UnitVector();
    const Eigen::Vector3d a_c_true = T_wc.q.conjugate() * a_w;
    double angle = random.Uniform(0.0, 1.5);
    if (trial % 4 == 0) angle = 1e-6;
    if (trial % 7 == 0) angle = random.Uniform(1.7, 3.0);
    // A full (non-diagonal) square-root information.
    TranslationComponent component{
        T_wc.Inverse() * t_wo + random.NormalVector(0.2),
        Eigen::Matrix3d::Identity() / random.Uniform(0.02, 0.2),
        1.0};
    for (int row = 0; row < 3; ++row) {
      component.sqrt_info.row(row) += random.NormalVector(2.0).transpose();
    }
    AxisMeasurement axis =
        Axis(Eigen::AngleAxisd(angle, AnyPerpendicular(a_c_true)) * a_c_true,
             random.Uniform(0.05, 0.3),
             random.Uniform(0.5, 3.0));
    axis.sqrt_info(0, 1) = random.Uniform(-3.0, 3.0);
    const Eigen::Matrix<double, 3, 2> basis = TangentBasis(axis.a_c);
    const ContinuousComponentCost hand(component, axis, basis);
    const ceres::
        AutoDiffCostFunction<ContinuousModel::ComponentFunctor, 5, 4, 3, 3, 3>
            autodiff(
                new ContinuousModel::ComponentFunctor{component, axis, basis});

    ContinuousState state(T_wc, t_wo, a_w);
    Eigen::Map<Eigen::Vector4d>(state.camera.q) *= random.Uniform(0.9, 1.1);
    Eigen::Map<Eigen::Vector3d>(state.a_w) *= random.Uniform(0.9, 1.1);
    const auto h = testing::EvaluateWithJacobians(hand, state.Parameters());
    const auto a = testing::EvaluateWithJacobians(autodiff, state.Parameters());
    ASSERT_TRUE(h.ok && a.ok);
    EXPECT_LE((h.residuals - a.residuals).cwiseAbs().maxCoeff(),
              1e-10 * std::max(1.0, a.residuals.cwiseAbs().maxCoeff()))
        << "trial " << trial;
    for (int b = 0; b < 4; ++b) {
      const double scale = std::max(1.0, a.jacobians[b].cwiseAbs().maxCoeff());
      EXPECT_LE((h.jacobians[b] - a.jacobians[b]).cwiseAbs().maxCoeff(),
                1e-10 * scale)
          << "trial " << trial << " block " << b << "\nhand\n"
          << h.jacobians[b] << "\nautodiff\n"
          << a.jacobians[b];
    }
  }
}

TEST(ContinuousObjectEdgeTest, RejectsInvalidInput) {
  std::unique_ptr<ContinuousObjectEdge> edge;
  const AxisMeasurement axis = Axis(Eigen::Vector3d::UnitZ(), 0.1, 1.0);
  EXPECT_EQ(
      CreateContinuousObjectEdge({}, axis, MixtureOptions(), &edge).message(),
      "a continuous edge needs at least one hypothesis");
  const TranslationComponent inf{
      Eigen::Vector3d(INFINITY, 0, 0), Eigen::Matrix3d::Identity(), 1.0};
  EXPECT_EQ(CreateContinuousObjectEdge({inf}, axis, MixtureOptions(), &edge)
                .message(),
            "hypothesis 0: translation is not finite");
  AxisMeasurement bad_axis = axis;
  bad_axis.a_c = Eigen::Vector3d(0, 0, 2);
  const TranslationComponent ok{
      Eigen::Vector3d(0, 0, 1), Eigen::Matrix3d::Identity(), 1.0};
  EXPECT_EQ(CreateContinuousObjectEdge({ok}, bad_axis, MixtureOptions(), &edge)
                .message(),
            "axis: a_c must be a finite unit vector");
  EXPECT_EQ(edge, nullptr);
}

}  // namespace
}  // namespace symba
