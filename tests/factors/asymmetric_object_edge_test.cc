#include "symba/factors/asymmetric_object_edge.h"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "factors/factor_test_util.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/se3.h"
#include "test_support/random.h"

namespace symba {
namespace {

using testing::PoseBlocks;

std::unique_ptr<AsymmetricObjectEdge> MakeEdge(
    std::vector<PoseComponent> components,
    const MixtureOptions& options = MixtureOptions()) {
  std::unique_ptr<AsymmetricObjectEdge> edge;
  const Status status =
      CreateAsymmetricObjectEdge(std::move(components), options, &edge);
  EXPECT_TRUE(status.ok()) << status.message();
  return edge;
}

// Blocks of a state: camera and object poses.
struct State {
  PoseBlocks camera;
  PoseBlocks object;
  State(const Rigid3d& T_wc, const Rigid3d& T_wo)
      : camera(T_wc), object(T_wo) {}
  std::vector<double*> Parameters() {
    return {camera.q, camera.t, object.q, object.t};
  }
};

Rigid3d Translation(double x, double y, double z) {
  return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, z));
}

TEST(AsymmetricObjectEdgeTest, ZeroResidualAtTheTrueState) {
  testing::TestRandom random(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Rigid3d T_wo(random.Rotation(), random.NormalVector(2.0));
    const Rigid3d T_co = T_wc.Inverse() * T_wo;
    auto edge = MakeEdge({{T_co, IsotropicPoseSqrtInfo(0.05, 0.1), 1.0}});
    State state(T_wc, T_wo);
    const auto e = testing::EvaluateWithJacobians(*edge, state.Parameters());
    ASSERT_TRUE(e.ok);
    EXPECT_LT(e.residuals.norm(), 1e-12);
  }
}

TEST(AsymmetricObjectEdgeTest, HandComputedTranslationAndRotationErrors) {
  // Camera at the origin; hypothesis: object 2 m ahead, unrotated.
  const Rigid3d T_co = Translation(0, 0, 2);
  auto edge = MakeEdge({{T_co, IsotropicPoseSqrtInfo(0.05, 0.1), 1.0}});

  // Object 0.1 m to the right of the hypothesis: T_co^j T_oc = (I, (-0.1,0,0))
  // so e = [-0.1, 0, 0, 0, 0, 0] and r = e / 0.05 on the rho rows.
  State shifted(Rigid3d::Identity(), Translation(0.1, 0, 2));
  const auto a = testing::EvaluateWithJacobians(*edge, shifted.Parameters());
  ASSERT_TRUE(a.ok);
  Eigen::Matrix<double, 7, 1> expected_a;
  expected_a << -2.0, 0, 0, 0, 0, 0, 0;
  EXPECT_LT((a.residuals - expected_a).norm(), 1e-12)
      << a.residuals.transpose();

  // Object yawed by 0.3 rad about the camera z axis (its own z): T_oc =
  // (Rz(-0.3), (0,0,-2)), T_co^j T_oc = (Rz(-0.3), 0): e = [0,0,0, 0,0,-0.3],
  // r = e / 0.1 on the omega rows.
  const Rigid3d T_wo(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(0, 0, 2));
  State yawed(Rigid3d::Identity(), T_wo);
  const auto b = testing::EvaluateWithJacobians(*edge, yawed.Parameters());
  ASSERT_TRUE(b.ok);
  Eigen::Matrix<double, 7, 1> expected_b;
  expected_b << 0, 0, 0, 0, 0, -3.0, 0;
  EXPECT_LT((b.residuals - expected_b).norm(), 1e-12)
      << b.residuals.transpose();
}

// DetectionSqrtInfo: the detection 2 m ahead, the estimated object turned
// by 0.01 rad about its own centre (the camera's y axis), its position
// exact. The log error carries the turn in rho too, omega x t_co = 2 cm
// across the line of sight: whitened at 5 cm, 0.4 on the x row. With the
// position's and rotation's errors independent it is left in the rotation
// rows (-0.1 on y) and the position rows are zero: the measured position
// is the estimate's, and rho + omega x t_co is exactly J_r(omega)^-1 times
// the position error (V(omega) Hat(omega) = Exp(omega) - I). A pure shift
// of 0.1 m reads the same either way.
TEST(AsymmetricObjectEdgeTest, IndependentErrorsKeepTheTurnOutOfThePosition) {
  const Rigid3d T_co = Translation(0, 0, 2);
  const Matrix6d independent = IsotropicPoseSqrtInfo(0.05, 0.1);
  auto log_edge = MakeEdge({{T_co, independent, 1.0}});
  auto edge = MakeEdge({{T_co, DetectionSqrtInfo(independent, T_co.t), 1.0}});

  const double turn = 0.01;
  State turned(Rigid3d::Identity(),
               Rigid3d(Eigen::Quaterniond(
                           Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitY())),
                       Eigen::Vector3d(0, 0, 2)));
  const auto a = testing::EvaluateWithJacobians(*log_edge, turned.Parameters());
  const auto b = testing::EvaluateWithJacobians(*edge, turned.Parameters());
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_NEAR(a.residuals(0), 2.0 * std::sin(turn) / 0.05, 0.002);
  EXPECT_LT(b.residuals.head<3>().norm(), 1e-9) << b.residuals.transpose();
  EXPECT_NEAR(b.residuals(4), -turn / 0.1, 1e-9);
  EXPECT_LT((a.residuals.tail<4>() - b.residuals.tail<4>()).norm(), 1e-12);

  State shifted(Rigid3d::Identity(), Translation(0.1, 0, 2));
  const auto c =
      testing::EvaluateWithJacobians(*log_edge, shifted.Parameters());
  const auto d = testing::EvaluateWithJacobians(*edge, shifted.Parameters());
  ASSERT_TRUE(c.ok && d.ok);
  Eigen::Matrix<double, 7, 1> expected;
  expected << -2.0, 0, 0, 0, 0, 0, 0;
  EXPECT_LT((c.residuals - expected).norm(), 1e-12);
  EXPECT_LT((d.residuals - expected).norm(), 1e-12);
}

// Random states for the gradient check: hypotheses around the true T_co, the
// estimate perturbed (the states of every other ten with DetectionSqrtInfo,
// so that each kind below meets both); every tenth state puts the estimate
// within 1e-6 rad of a hypothesis (near identity error), every tenth + 5 at
// pi - 1e-3 from it.
TEST(AsymmetricObjectEdgeTest, GradientCheckerPassesAt240RandomStates) {
  testing::TestRandom random(12);
  ceres::EigenQuaternionManifold quaternion;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion, nullptr, &quaternion, nullptr};
  for (int trial = 0; trial < 240; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    Rigid3d T_wo(random.Rotation(), T_wc * Eigen::Vector3d(0, 0, 2.5));
    const Rigid3d T_co_true = T_wc.Inverse() * T_wo;
    std::vector<PoseComponent> components;
    const int n = 1 + trial % 7;
    for (int j = 0; j < n; ++j) {
      const Rigid3d noise(random.RotationOfAngle(random.Uniform(0.0, 0.5)),
                          random.NormalVector(0.1));
      components.push_back(testing::RandomGradientCheckComponent(
          T_co_true * noise, trial, &random));
    }
    if (trial % 10 == 0) {
      // Estimate within 1e-6 rad and 1e-6 m of hypothesis 0.
      const Rigid3d tiny(random.RotationOfAngle(1e-6),
                         random.NormalVector(1e-6));
      T_wo = T_wc * components[0].T_co * tiny;
    } else if (trial % 10 == 5) {
      // Relative rotation pi - 1e-3 away from hypothesis 0.
      const Rigid3d flip(random.RotationOfAngle(kPi - 1e-3),
                         Eigen::Vector3d::Zero());
      T_wo = T_wc * components[0].T_co * flip;
    }
    auto edge = MakeEdge(components);
    State state(T_wc, T_wo);
    std::string message;
    EXPECT_TRUE(testing::GradientIsCorrect(
        *edge, manifolds, state.Parameters(), 1e-6, &message))
        << "trial " << trial << "\n"
        << message;
  }
}

// A random square-root information: isotropic (diagonal), every third one
// block-diagonal with full 3 x 3 blocks, every third + 1 dense.
Matrix6d RandomSqrtInfo(testing::TestRandom& random, int kind) {
  Matrix6d L = IsotropicPoseSqrtInfo(random.Uniform(0.02, 0.2),
                                     random.Uniform(0.05, 0.3));
  if (kind % 3 == 0) return L;
  for (int row = 0; row < 6; ++row) {
    for (int col = 0; col < 6; ++col) {
      const bool same_block = (row < 3) == (col < 3);
      if (row != col && (same_block || kind % 3 == 1)) {
        L(row, col) = random.Normal(2.0);
      }
    }
  }
  return L;
}

// The hand-written winner (AsymmetricComponentCost) against autodiff of the
// templated residual, in the ambient coordinates of every block, at 200
// random states: both quaternions off the unit sphere by up to 10 %, errors
// from 1e-6 rad (LogSE3's series branches) and 5e-3 rad (its V^-1 series) to
// pi - 1e-3, and diagonal, block-diagonal and dense L.
TEST(AsymmetricObjectEdgeTest, HandWrittenJacobianEqualsAutoDiff) {
  testing::TestRandom random(13);
  for (int trial = 0; trial < 200; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Rigid3d T_wo(random.Rotation(), T_wc * Eigen::Vector3d(0, 0, 2.5));
    double angle = random.Uniform(0.0, 3.0);
    if (trial % 10 == 0) angle = 1e-6;
    if (trial % 10 == 1) angle = 5e-3;
    if (trial % 10 == 5) angle = kPi - 1e-3;
    const Rigid3d offset(random.RotationOfAngle(angle),
                         random.NormalVector(trial % 10 == 0 ? 1e-6 : 0.1));
    const PoseComponent component{
        (T_wc.Inverse() * T_wo) * offset, RandomSqrtInfo(random, trial), 1.0};
    const AsymmetricComponentCost hand(component);
    const ceres::AutoDiffCostFunction<AsymmetricPoseModel::ComponentFunctor,
                                      6,
                                      4,
                                      3,
                                      4,
                                      3>
        autodiff(new AsymmetricPoseModel::ComponentFunctor{component});
    State state(T_wc, T_wo);
    Eigen::Map<Eigen::Vector4d>(state.camera.q) *= random.Uniform(0.9, 1.1);
    Eigen::Map<Eigen::Vector4d>(state.object.q) *= random.Uniform(0.9, 1.1);
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

// The selection skips components by PoseMixture::SquaredNormLowerBound. At
// 300 random states with up to 30 hypotheses (diagonal, block-diagonal and
// dense L; some near, some far; with and without the null hypothesis) the
// bound never exceeds the exact norm and Select picks what an exhaustive
// search picks. For isotropic L and errors under 0.5 rad the bound is within
// 5 % of the norm (it prunes well).
TEST(AsymmetricObjectEdgeTest, LowerBoundNeverChangesTheSelection) {
  testing::TestRandom random(14);
  for (int trial = 0; trial < 300; ++trial) {
    const Rigid3d T_wc(random.Rotation(), random.NormalVector(2.0));
    const Rigid3d T_wo(random.Rotation(), T_wc * Eigen::Vector3d(0, 0, 2.5));
    const Rigid3d T_co = T_wc.Inverse() * T_wo;
    const int n = 1 + trial % 30;
    std::vector<PoseComponent> components;
    for (int j = 0; j < n; ++j) {
      const double angle =
          j % 4 == 3 ? random.Uniform(0.0, kPi) : random.Uniform(0.0, 0.3);
      const Rigid3d offset(random.RotationOfAngle(angle),
                           random.NormalVector(j % 4 == 3 ? 0.5 : 0.05));
      components.push_back({T_co * offset,
                            RandomSqrtInfo(random, trial / 30),
                            random.Uniform(0.1, 1.0)});
    }
    MixtureOptions options;
    options.use_null_hypothesis = trial % 2 == 1;
    options.null_sigma_scale = 3.0;
    options.null_weight = 0.05;
    auto edge = MakeEdge(components, options);
    State state(T_wc, T_wo);
    Eigen::Map<Eigen::Vector4d>(state.camera.q) *= random.Uniform(0.999, 1.001);
    const auto parameters = state.Parameters();

    const AsymmetricPoseModel& model = edge->model();
    Rigid3d T_oc;
    ASSERT_TRUE(model.Prepare(parameters.data(), &T_oc));
    double weight_sum = 0.0;
    for (const PoseComponent& c : components) weight_sum += c.weight;
    int best = -1;
    int nearest = -1;
    double best_cost = INFINITY;
    double nearest_squared_norm = INFINITY;
    for (int j = 0; j < n; ++j) {
      const double squared_norm = model.MixtureSquaredNorm(T_oc, j);
      const double bound = model.MixtureSquaredNormLowerBound(T_oc, j);
      EXPECT_LE(bound, squared_norm) << "trial " << trial << " j " << j;
      if (trial / 30 % 3 == 0 && j % 4 != 3) {
        EXPECT_GE(bound, 0.95 * squared_norm) << "trial " << trial;
      }
      const double cost = 0.5 * squared_norm -
                          std::log(components[j].weight / weight_sum) -
                          model.LogDetSqrtInfo(j);
      if (cost < best_cost) {
        best_cost = cost;
        best = j;
      }
      if (squared_norm < nearest_squared_norm) {
        nearest_squared_norm = squared_norm;
        nearest = j;
      }
    }
    bool is_null = false;
    if (options.use_null_hypothesis) {
      const double null_cost =
          0.5 * nearest_squared_norm / 9.0 - std::log(options.null_weight) -
          model.LogDetSqrtInfo(nearest) + 6.0 * std::log(3.0);
      if (null_cost < best_cost) {
        best = nearest;
        is_null = true;
      }
    }
    MixtureSelection selection;
    ASSERT_TRUE(edge->Select(parameters.data(), &selection));
    EXPECT_EQ(selection.component, best) << "trial " << trial;
    EXPECT_EQ(selection.is_null, is_null) << "trial " << trial;
  }
}

// Two hypotheses 1 m apart along x with unit information: r_j = a_j - x on
// the first row. With weights w_0, w_1 the winner switches where
// 0.5 (x - a_0)^2 - log w_0 = 0.5 (x - a_1)^2 - log w_1, i.e. at
// x* = 0.5 + log(w_0 / w_1) for a_0 = 0, a_1 = 1.
class WinnerSwitchTest : public ::testing::TestWithParam<double> {};

TEST_P(WinnerSwitchTest, SwitchesExactlyWhereTheNormalisationSays) {
  const double w0 = GetParam();
  const double w1 = 1.0 - w0;
  const Matrix6d unit = Matrix6d::Identity();
  auto edge = MakeEdge(
      {{Translation(0, 0, 2), unit, w0}, {Translation(1, 0, 2), unit, w1}});
  auto only0 = MakeEdge({{Translation(0, 0, 2), unit, 1.0}});
  auto only1 = MakeEdge({{Translation(1, 0, 2), unit, 1.0}});
  const double x_switch = 0.5 + std::log(w0 / w1);
  const double k_gap = std::abs(std::log(w0 / w1));  // k_loser - k_winner

  double cost_before = 0.0;
  for (const double dx : {-1e-7, 1e-7}) {
    const double x = x_switch + dx;
    State state(Rigid3d::Identity(), Translation(x, 0, 2));
    MixtureSelection selection;
    ASSERT_TRUE(edge->Select(state.Parameters().data(), &selection));
    const int expected_winner = dx < 0 ? 0 : 1;
    EXPECT_EQ(selection.component, expected_winner) << "x = " << x;
    EXPECT_FALSE(selection.is_null);

    const auto mixed =
        testing::EvaluateWithJacobians(*edge, state.Parameters());
    const auto single = testing::EvaluateWithJacobians(
        expected_winner == 0 ? *only0 : *only1, state.Parameters());
    ASSERT_TRUE(mixed.ok && single.ok);
    // The winner's residual and Jacobian, plus the normalisation row.
    EXPECT_LT((mixed.residuals.head<6>() - single.residuals.head<6>()).norm(),
              1e-12);
    for (int b = 0; b < 4; ++b) {
      EXPECT_LT((mixed.jacobians[b].topRows(6) - single.jacobians[b].topRows(6))
                    .norm(),
                1e-12);
      EXPECT_EQ(mixed.jacobians[b].row(6).norm(), 0.0);
    }
    const bool winner_is_less_likely = (expected_winner == 0) != (w0 >= w1);
    const double expected_norm_row =
        winner_is_less_likely ? std::sqrt(2.0 * k_gap) : 0.0;
    EXPECT_NEAR(mixed.residuals(6), expected_norm_row, 1e-12);

    // The total cost is continuous across the switch.
    const double cost = 0.5 * mixed.residuals.squaredNorm();
    if (dx < 0) {
      cost_before = cost;
    } else {
      EXPECT_NEAR(cost, cost_before, 1e-6);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Weights,
                         WinnerSwitchTest,
                         ::testing::Values(0.5, 0.8, 0.2, 0.95));

TEST(AsymmetricObjectEdgeTest, InformationEntersTheNormalisation) {
  // Equal weights, the second hypothesis 2x more certain (sigma halved): its
  // k is lower by 6 log 2, so the first hypothesis pays sqrt(2 * 6 log 2).
  auto edge =
      MakeEdge({{Translation(0, 0, 2), Matrix6d::Identity(), 1.0},
                {Translation(5, 0, 2), 2.0 * Matrix6d::Identity(), 1.0}});
  State state(Rigid3d::Identity(), Translation(0, 0, 2));
  const auto e = testing::EvaluateWithJacobians(*edge, state.Parameters());
  ASSERT_TRUE(e.ok);
  EXPECT_NEAR(e.residuals(6), std::sqrt(12.0 * std::log(2.0)), 1e-12);
  EXPECT_LT(e.residuals.head<6>().norm(), 1e-12);
}

TEST(AsymmetricObjectEdgeTest, NullHypothesisBoundsTheCostOfAWrongAssociation) {
  MixtureOptions options;
  options.use_null_hypothesis = true;
  options.null_weight = 1e-3;
  options.null_sigma_scale = 10.0;
  const Matrix6d unit = Matrix6d::Identity();
  auto edge = MakeEdge({{Translation(0, 0, 2), unit, 1.0}}, options);

  // Close to the hypothesis the hypothesis wins.
  State near(Rigid3d::Identity(), Translation(0.5, 0, 2));
  MixtureSelection selection;
  ASSERT_TRUE(edge->Select(near.Parameters().data(), &selection));
  EXPECT_FALSE(selection.is_null);

  // Far away the null component wins: residual scaled by 1/10, and the
  // normalisation row carries k_null - k_min = -log(1e-3) + 6 log 10.
  State far(Rigid3d::Identity(), Translation(20, 0, 2));
  ASSERT_TRUE(edge->Select(far.Parameters().data(), &selection));
  EXPECT_TRUE(selection.is_null);
  EXPECT_EQ(selection.component, 0);
  const auto e = testing::EvaluateWithJacobians(*edge, far.Parameters());
  ASSERT_TRUE(e.ok);
  EXPECT_NEAR(e.residuals(0), -20.0 / 10.0, 1e-12);
  EXPECT_NEAR(e.residuals(6),
              std::sqrt(2.0 * (-std::log(1e-3) + 6.0 * std::log(10.0))),
              1e-9);
  // Switch point: 0.5 x^2 = 0.5 x^2 / 100 - log(1e-3) + 6 log 10.
  const double x_switch = std::sqrt(
      2.0 * (-std::log(1e-3) + 6.0 * std::log(10.0)) / (1.0 - 1.0 / 100.0));
  State before(Rigid3d::Identity(), Translation(x_switch - 1e-6, 0, 2));
  State after(Rigid3d::Identity(), Translation(x_switch + 1e-6, 0, 2));
  ASSERT_TRUE(edge->Select(before.Parameters().data(), &selection));
  EXPECT_FALSE(selection.is_null);
  ASSERT_TRUE(edge->Select(after.Parameters().data(), &selection));
  EXPECT_TRUE(selection.is_null);
}

TEST(AsymmetricObjectEdgeTest, RejectsInvalidComponentsWithAMessage) {
  std::unique_ptr<AsymmetricObjectEdge> edge;
  EXPECT_FALSE(CreateAsymmetricObjectEdge({}, MixtureOptions(), &edge).ok());

  PoseComponent nan_pose{
      Translation(std::nan(""), 0, 1), Matrix6d::Identity(), 1.0};
  Status status =
      CreateAsymmetricObjectEdge({nan_pose}, MixtureOptions(), &edge);
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.message(), "hypothesis 0: pose is not finite");

  PoseComponent zero_weight{Translation(0, 0, 1), Matrix6d::Identity(), 0.0};
  status = CreateAsymmetricObjectEdge({zero_weight}, MixtureOptions(), &edge);
  EXPECT_EQ(status.message(),
            "hypothesis 0: weight must be positive and finite");

  PoseComponent singular{Translation(0, 0, 1), Matrix6d::Zero(), 1.0};
  status = CreateAsymmetricObjectEdge({singular}, MixtureOptions(), &edge);
  EXPECT_EQ(status.message(),
            "hypothesis 0: square-root information is singular");

  PoseComponent good{Translation(0, 0, 1), Matrix6d::Identity(), 1.0};
  MixtureOptions bad_options;
  bad_options.use_null_hypothesis = true;
  bad_options.null_sigma_scale = 0.5;
  status = CreateAsymmetricObjectEdge({good}, bad_options, &edge);
  EXPECT_EQ(status.message(), "invalid mixture options");
  EXPECT_EQ(edge, nullptr);
}

TEST(AsymmetricObjectEdgeTest, NonFiniteParametersFailTheEvaluation) {
  auto edge = MakeEdge({{Translation(0, 0, 2), Matrix6d::Identity(), 1.0}});
  State state(Rigid3d::Identity(), Translation(std::nan(""), 0, 2));
  double residuals[7];
  EXPECT_FALSE(edge->Evaluate(state.Parameters().data(), residuals, nullptr));
}

}  // namespace
}  // namespace symba
