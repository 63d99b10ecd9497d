#include "symba/factors/discrete_object_edge.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "factors/factor_test_util.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/swing_twist.h"
#include "symba/manifolds/axis_manifold.h"
#include "test_support/random.h"

namespace symba {
namespace {

using testing::PoseBlocks;

std::unique_ptr<DiscreteObjectEdge> MakeEdge(
    std::vector<PoseComponent> components, const SymmetryAnchor& anchor) {
  std::unique_ptr<DiscreteObjectEdge> edge;
  const Status status = CreateDiscreteObjectEdge(
      std::move(components), anchor, MixtureOptions(), &edge);
  EXPECT_TRUE(status.ok()) << status.message();
  return edge;
}

// Blocks of a state: camera pose, object position, world axis, one angle.
struct DiscreteState {
  PoseBlocks camera;
  double t_wo[3];
  double a_w[3];
  double theta;
  DiscreteState(const Rigid3d& T_wc,
                const Eigen::Vector3d& position,
                const Eigen::Vector3d& axis,
                double angle)
      : camera(T_wc), theta(angle) {
    Eigen::Map<Eigen::Vector3d> t_map(t_wo);
    Eigen::Map<Eigen::Vector3d> a_map(a_w);
    t_map = position;
    a_map = axis.normalized();
  }
  std::vector<double*> Parameters() {
    return {camera.q, camera.t, t_wo, a_w, &theta};
  }
};

Eigen::Quaterniond AngleAxis(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

TEST(DiscreteObjectEdgeTest,
     RotationModelReproducesTheAnchorAndTwistsAboutTheAxis) {
  testing::TestRandom random(21);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Quaterniond q_wo = random.Rotation();
    const Eigen::Vector3d a_o = random.UnitVector();
    const SymmetryAnchor anchor = SymmetryAnchor::FromObjectRotation(q_wo, a_o);
    // theta = 0 and a_w = a_w0 give the anchor's rotation.
    EXPECT_LT(
        SymmetricObjectRotation(anchor, anchor.a_w0, 0.0).angularDistance(q_wo),
        1e-12);
    // theta rotates about the object's own axis: R_wo_i = R_wo Rot(a_o, theta).
    const double theta = random.Uniform(-kPi, kPi);
    EXPECT_LT(SymmetricObjectRotation(anchor, anchor.a_w0, theta)
                  .angularDistance(q_wo * AngleAxis(theta, a_o)),
              1e-12);
    // Whatever the angle, the object axis lands on a_w.
    const Eigen::Vector3d a_w = random.UnitVector();
    EXPECT_LT((SymmetricObjectRotation(anchor, a_w, theta) * a_o - a_w).norm(),
              1e-12);
  }
}

TEST(DiscreteObjectEdgeTest, ZeroResidualAtTheTrueState) {
  testing::TestRandom random(22);
  for (int trial = 0; trial < 20; ++trial) {
    const SymmetryAnchor anchor = SymmetryAnchor::FromObjectRotation(
        random.Rotation(), random.UnitVector());
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Eigen::Vector3d t_wo = random.NormalVector(2.0);
    const Eigen::Vector3d a_w = random.UnitVector();
    const double theta = random.Uniform(-kPi, kPi);
    const Rigid3d T_wo(SymmetricObjectRotation(anchor, a_w, theta), t_wo);
    auto edge = MakeEdge(
        {{T_wc.Inverse() * T_wo, IsotropicPoseSqrtInfo(0.05, 0.1), 1.0}},
        anchor);
    DiscreteState state(T_wc, t_wo, a_w, theta);
    const auto e = testing::EvaluateWithJacobians(*edge, state.Parameters());
    ASSERT_TRUE(e.ok);
    EXPECT_LT(e.residuals.norm(), 1e-12);
  }
}

TEST(DiscreteObjectEdgeTest, HandComputedAngleAndAxisErrors) {
  // Anchor: identity, axis z. Hypothesis: object at the camera, unrotated.
  const SymmetryAnchor anchor;
  auto edge = MakeEdge(
      {{Rigid3d::Identity(), IsotropicPoseSqrtInfo(0.05, 0.1), 1.0}}, anchor);
  // theta = 0.3 about z: R_wo = Rz(0.3), e = [0,0,0, 0,0,-0.3], r = e / 0.1.
  DiscreteState yawed(Rigid3d::Identity(),
                      Eigen::Vector3d::Zero(),
                      Eigen::Vector3d::UnitZ(),
                      0.3);
  auto a = testing::EvaluateWithJacobians(*edge, yawed.Parameters());
  ASSERT_TRUE(a.ok);
  Eigen::Matrix<double, 7, 1> expected;
  expected << 0, 0, 0, 0, 0, -3.0, 0;
  EXPECT_LT((a.residuals - expected).norm(), 1e-12) << a.residuals.transpose();
  // Axis tilted by 0.2 rad about x: Swing(z -> a_w) = Rx(0.2) = R_wo,
  // e = [0,0,0, -0.2,0,0], r = e / 0.1.
  DiscreteState tilted(
      Rigid3d::Identity(),
      Eigen::Vector3d::Zero(),
      AngleAxis(0.2, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ(),
      0.0);
  auto b = testing::EvaluateWithJacobians(*edge, tilted.Parameters());
  ASSERT_TRUE(b.ok);
  expected << 0, 0, 0, -2.0, 0, 0, 0;
  EXPECT_LT((b.residuals - expected).norm(), 1e-12) << b.residuals.transpose();
}

// 240 random states: random object-frame axes; every fourth state has a
// vertical world axis (the pole of the paper's spherical angles), every fifth
// an axis equal to the anchor's; otherwise the anchor is up to 0.5 rad from
// the true rotation (Swing is singular only at a_w = -a_w0, which re-anchoring
// avoids); angles up to +-pi; hypotheses of which one is within 1e-6 or
// pi - 1e-3 rad of the estimate.
TEST(DiscreteObjectEdgeTest, GradientCheckerPassesAt240RandomStates) {
  testing::TestRandom random(23);
  ceres::EigenQuaternionManifold quaternion;
  AxisManifold axis_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion, nullptr, nullptr, &axis_manifold, nullptr};
  for (int trial = 0; trial < 240; ++trial) {
    const Eigen::Vector3d a_o =
        trial % 3 == 0 ? Eigen::Vector3d::UnitZ() : random.UnitVector();
    Eigen::Quaterniond q_wo_true = random.Rotation();
    if (trial % 4 == 0) {
      q_wo_true =
          MinimalRotation(a_o, Eigen::Vector3d(Eigen::Vector3d::UnitZ())) *
          AngleAxis(random.Uniform(-kPi, kPi), a_o);
    }
    const Eigen::Vector3d a_w = q_wo_true * a_o;
    const Eigen::Quaterniond q_anchor =
        trial % 5 == 0
            ? q_wo_true
            : q_wo_true * ExpSO3(Eigen::Vector3d(random.NormalVector(0.3)));
    const SymmetryAnchor anchor =
        SymmetryAnchor::FromObjectRotation(q_anchor, a_o);
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Eigen::Vector3d t_wo = T_wc * Eigen::Vector3d(0, 0, 2.5);
    const double theta = random.Uniform(-kPi, kPi);
    const Rigid3d T_wo(SymmetricObjectRotation(anchor, a_w, theta), t_wo);
    const Rigid3d T_co = T_wc.Inverse() * T_wo;
    std::vector<PoseComponent> components;
    const int n = 1 + trial % 5;
    for (int j = 0; j < n; ++j) {
      Rigid3d offset(random.RotationOfAngle(random.Uniform(0.0, 0.4)),
                     random.NormalVector(0.1));
      if (j == 0 && trial % 10 == 3) {
        offset =
            Rigid3d(random.RotationOfAngle(1e-6), random.NormalVector(1e-6));
      } else if (j == 0 && trial % 10 == 7) {
        offset = Rigid3d(random.RotationOfAngle(kPi - 1e-3),
                         Eigen::Vector3d::Zero());
      }
      components.push_back(
          testing::RandomGradientCheckComponent(T_co * offset, trial, &random));
    }
    auto edge = MakeEdge(components, anchor);
    DiscreteState state(T_wc, t_wo, a_w, theta);
    std::string message;
    EXPECT_TRUE(testing::GradientIsCorrect(
        *edge, manifolds, state.Parameters(), 1e-6, &message))
        << "trial " << trial << "\n"
        << message;
  }
}

// The hand-written winner (DiscreteComponentCost) against autodiff of the
// templated residual, in the ambient coordinates of every block, at 200
// random states: q_wc and a_w off the unit sphere by up to 10 %, anchors up
// to 0.5 rad from the rotation (every fifth exact), angles up to +-pi, errors
// from 1e-6 rad to pi - 1e-3, and a dense L every third state.
TEST(DiscreteObjectEdgeTest, HandWrittenJacobianEqualsAutoDiff) {
  testing::TestRandom random(24);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d a_o =
        trial % 3 == 0 ? Eigen::Vector3d::UnitZ() : random.UnitVector();
    const Eigen::Quaterniond q_wo_true = random.Rotation();
    const Eigen::Vector3d a_w = q_wo_true * a_o;
    const Eigen::Quaterniond q_anchor =
        trial % 5 == 0
            ? q_wo_true
            : q_wo_true * ExpSO3(Eigen::Vector3d(random.NormalVector(0.3)));
    const SymmetryAnchor anchor =
        SymmetryAnchor::FromObjectRotation(q_anchor, a_o);
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Eigen::Vector3d t_wo = T_wc * Eigen::Vector3d(0, 0, 2.5);
    const double theta = random.Uniform(-kPi, kPi);
    const Rigid3d T_wo(SymmetricObjectRotation(anchor, a_w, theta), t_wo);
    double angle = random.Uniform(0.0, 3.0);
    if (trial % 10 == 0) angle = 1e-6;
    if (trial % 10 == 5) angle = kPi - 1e-3;
    const Rigid3d offset(random.RotationOfAngle(angle),
                         random.NormalVector(0.1));
    PoseComponent component{(T_wc.Inverse() * T_wo) * offset,
                            IsotropicPoseSqrtInfo(random.Uniform(0.02, 0.2),
                                                  random.Uniform(0.05, 0.3)),
                            1.0};
    if (trial % 3 == 1) {
      for (int row = 0; row < 6; ++row) {
        component.sqrt_info.row(row).head<3>() +=
            random.NormalVector(2.0).transpose();
        component.sqrt_info.row(row).tail<3>() +=
            random.NormalVector(2.0).transpose();
      }
    }
    const DiscreteComponentCost hand(component, anchor);
    const ceres::AutoDiffCostFunction<DiscretePoseModel::ComponentFunctor,
                                      6,
                                      4,
                                      3,
                                      3,
                                      3,
                                      1>
        autodiff(new DiscretePoseModel::ComponentFunctor{component, anchor});
    DiscreteState state(T_wc, t_wo, a_w, theta);
    Eigen::Map<Eigen::Vector4d>(state.camera.q) *= random.Uniform(0.9, 1.1);
    Eigen::Map<Eigen::Vector3d>(state.a_w) *= random.Uniform(0.9, 1.1);
    std::string message;
    EXPECT_TRUE(testing::EvaluationsAgree(
        testing::EvaluateWithJacobians(hand, state.Parameters()),
        testing::EvaluateWithJacobians(autodiff, state.Parameters()),
        1e-10,
        &message))
        << "trial " << trial << "\n"
        << message;
  }
}

// Two hypotheses of one cluster, 1 rad apart about the axis, weights 0.7 and
// 0.3, unit information: e_j = [0,0,0, 0,0, phi_j - theta] so the winner
// switches at theta* = 0.5 + log(0.7 / 0.3).
TEST(DiscreteObjectEdgeTest, WinnerSwitchesAtTheWeightedBoundary) {
  const SymmetryAnchor anchor;
  const Rigid3d h0 = Rigid3d::Identity();
  const Rigid3d h1(AngleAxis(1.0, Eigen::Vector3d::UnitZ()),
                   Eigen::Vector3d::Zero());
  auto edge = MakeEdge(
      {{h0, Matrix6d::Identity(), 0.7}, {h1, Matrix6d::Identity(), 0.3}},
      anchor);
  auto only1 = MakeEdge({{h1, Matrix6d::Identity(), 1.0}}, anchor);
  const double theta_switch = 0.5 + std::log(0.7 / 0.3);
  MixtureSelection selection;
  DiscreteState before(Rigid3d::Identity(),
                       Eigen::Vector3d::Zero(),
                       Eigen::Vector3d::UnitZ(),
                       theta_switch - 1e-7);
  ASSERT_TRUE(edge->Select(before.Parameters().data(), &selection));
  EXPECT_EQ(selection.component, 0);
  DiscreteState after(Rigid3d::Identity(),
                      Eigen::Vector3d::Zero(),
                      Eigen::Vector3d::UnitZ(),
                      theta_switch + 1e-7);
  ASSERT_TRUE(edge->Select(after.Parameters().data(), &selection));
  EXPECT_EQ(selection.component, 1);
  const auto mixed = testing::EvaluateWithJacobians(*edge, after.Parameters());
  const auto single =
      testing::EvaluateWithJacobians(*only1, after.Parameters());
  ASSERT_TRUE(mixed.ok && single.ok);
  for (int b = 0; b < 5; ++b) {
    EXPECT_LT(
        (mixed.jacobians[b].topRows(6) - single.jacobians[b].topRows(6)).norm(),
        1e-12);
  }
  EXPECT_NEAR(mixed.residuals(6), std::sqrt(2.0 * std::log(0.7 / 0.3)), 1e-12);
}

TEST(DiscreteObjectEdgeTest, RejectsAnInconsistentAnchor) {
  SymmetryAnchor anchor;
  anchor.a_w0 = Eigen::Vector3d::UnitX();  // R_base a_o = z, not x
  std::unique_ptr<DiscreteObjectEdge> edge;
  const Status status = CreateDiscreteObjectEdge(
      {{Rigid3d::Identity(), Matrix6d::Identity(), 1.0}},
      anchor,
      MixtureOptions(),
      &edge);
  EXPECT_EQ(status.message(), "symmetry anchor: R_base a_o must equal a_w0");
  EXPECT_EQ(edge, nullptr);
}

}  // namespace
}  // namespace symba
