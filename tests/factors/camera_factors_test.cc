// Tests of the camera-side factors: RelativePoseFactor (odometry between two
// keyframes), PosePriorFactor and ReprojectionFactor (pinhole, map point).
//
// For each factor: zero residual at the true state, one value computed by
// hand, Jacobians against ceres::GradientChecker at random states (including
// estimate/measurement rotations near the identity and near pi), and small
// solves that must recover the truth from a perturbed start.

#include "symba/factors/pose_prior_factor.h"
#include "symba/factors/relative_pose_factor.h"
#include "symba/factors/reprojection_factor.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <ceres/numeric_diff_options.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "factors/factor_test_util.h"
#include "symba/factors/pose_component.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/rigid3.h"
#include "test_support/random.h"

namespace symba {
namespace {

// Gradient checks: per-entry relative error |a - b| / max(|a|, |b|) of the
// Jet Jacobian against Ridders-extrapolated numeric differences, in the
// tangent space of the quaternion blocks. The numeric side is good to ~1e-10
// absolute, so the worst case comes from entries that happen to be small
// (~1e-3): about 2e-7 over the states below (near pi), 5e-8 elsewhere.
constexpr double kGradientRelativePrecision = 1e-6;
// Residuals of states that reproduce the measurement exactly.
constexpr double kZeroResidualTolerance = 1e-12;
// Random states per factor for the gradient check.
constexpr int kGradientStatesPerRegime = 70;  // x 3 regimes = 210 states
constexpr int kReprojectionGradientStates = 210;

using testing::PoseBlocks;
// The blocks hold each pose's quaternion bit for bit.
constexpr testing::QuaternionStorage kAsGiven =
    testing::QuaternionStorage::kAsGiven;

Eigen::Quaterniond AngleAxis(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// The rotation angle of a^-1 b, accurate at every angle.
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

Rigid3d RandomPose(testing::TestRandom& random, double translation_sigma) {
  return Rigid3d(random.Rotation(), random.NormalVector(translation_sigma));
}

// A random upper-triangular square-root information with a positive
// diagonal, so that every residual row mixes several error components.
template <int kSize>
Eigen::Matrix<double, kSize, kSize> RandomSqrtInfo(testing::TestRandom& random,
                                                   double scale) {
  Eigen::Matrix<double, kSize, kSize> L =
      Eigen::Matrix<double, kSize, kSize>::Zero();
  for (int i = 0; i < kSize; ++i) {
    L(i, i) = scale * random.Uniform(0.5, 2.0);
    for (int j = i + 1; j < kSize; ++j)
      L(i, j) = scale * random.Uniform(-0.3, 0.3);
  }
  return L;
}

// The residual of `cost` at `parameters` (no Jacobians); false if Evaluate
// fails.
bool EvaluateResidual(const ceres::CostFunction& cost,
                      const std::vector<const double*>& parameters,
                      Eigen::VectorXd* residual) {
  residual->resize(cost.num_residuals());
  return cost.Evaluate(parameters.data(), residual->data(), nullptr);
}

// Evaluate with all Jacobians requested.
bool EvaluateWithJacobians(const ceres::CostFunction& cost,
                           const std::vector<const double*>& parameters) {
  const int rows = cost.num_residuals();
  Eigen::VectorXd residual(rows);
  std::vector<Eigen::MatrixXd> jacobians;
  std::vector<double*> jacobian_ptrs;
  for (const int size : cost.parameter_block_sizes()) {
    jacobians.emplace_back(rows, size);
  }
  for (Eigen::MatrixXd& J : jacobians) jacobian_ptrs.push_back(J.data());
  return cost.Evaluate(
      parameters.data(), residual.data(), jacobian_ptrs.data());
}

// Runs the gradient checker over many states of one factor and keeps the
// worst error and the log of the first failure.
class GradientCheckRecorder {
 public:
  void Probe(const ceres::CostFunction& cost,
             const std::vector<const ceres::Manifold*>& manifolds,
             const std::vector<const double*>& parameters,
             const std::string& state) {
    ceres::NumericDiffOptions options;
    // Ridders' first step is 2^5 max(s, s |x_j|) with s the relative initial
    // step size (default 1e-2, so at least 0.32). Near pi a step that large
    // flips the sign of the error quaternion's w (|w| ~ 5e-4 at pi - 1e-3),
    // where the logarithm jumps from +pi to -pi about the axis and the
    // "derivative" is garbage; s = 1e-6 keeps the first step on a quaternion
    // coordinate (|x_j| <= 1) at most 3.2e-5.
    options.ridders_relative_initial_step_size = 1e-6;
    const ceres::GradientChecker checker(&cost, &manifolds, options);
    ceres::GradientChecker::ProbeResults results;
    const bool ok =
        checker.Probe(parameters.data(), kGradientRelativePrecision, &results);
    ++probes_;
    max_error_ = std::max(max_error_, results.maximum_relative_error);
    if (!ok) {
      if (failures_ == 0) first_failure_ = state + "\n" + results.error_log;
      ++failures_;
    }
  }

  // Expects every probe to have passed; reports the worst error otherwise.
  void ExpectAllPassed(int min_probes) const {
    EXPECT_GE(probes_, min_probes);
    EXPECT_EQ(failures_, 0)
        << failures_ << " of " << probes_
        << " states failed; max relative error " << max_error_ << " (precision "
        << kGradientRelativePrecision << ")\n"
        << "first failure: " << first_failure_;
  }

 private:
  int probes_ = 0;
  int failures_ = 0;
  double max_error_ = 0.0;
  std::string first_failure_;
};

// How far the estimate's rotation is from the measurement's.
enum class Regime { kGeneric, kNearIdentity, kNearPi };

const char* RegimeName(Regime regime) {
  switch (regime) {
    case Regime::kGeneric:
      return "generic";
    case Regime::kNearIdentity:
      return "near identity";
    case Regime::kNearPi:
      return "near pi";
  }
  return "?";
}

// A random error transform E (estimate = measurement * E) whose rotation
// angle is set by `regime`.
Rigid3d RandomError(testing::TestRandom& random, Regime regime) {
  double angle = 0.0;
  switch (regime) {
    case Regime::kGeneric:
      angle = random.Uniform(0.0, 3.0);
      break;
    case Regime::kNearIdentity:
      angle = 1e-6;
      break;
    case Regime::kNearPi:
      angle = kPi - 1e-3;
      break;
  }
  return Rigid3d(random.RotationOfAngle(angle), random.NormalVector(0.5));
}

// Pinhole projection written out independently of the factor.
Eigen::Vector2d Project(const PinholeIntrinsics& K,
                        const Rigid3d& T_wc,
                        const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c =
      T_wc.q.toRotationMatrix().transpose() * (p_w - T_wc.t);
  return Eigen::Vector2d(K.fx * p_c.x() / p_c.z() + K.cx,
                         K.fy * p_c.y() / p_c.z() + K.cy);
}

PinholeIntrinsics TestIntrinsics() {
  PinholeIntrinsics K;
  K.fx = 500.0;
  K.fy = 500.0;
  K.cx = 320.0;
  K.cy = 240.0;
  return K;
}

// ---------------------------------------------------------------------------
// RelativePoseFactor

TEST(RelativePoseFactor, ZeroResidualWhenEstimateReproducesMeasurement) {
  testing::TestRandom random(101);
  for (int i = 0; i < 50; ++i) {
    const Rigid3d T_wa = RandomPose(random, 3.0);
    const Rigid3d T_wb = RandomPose(random, 3.0);
    const Rigid3d T_ab = T_wa.Inverse() * T_wb;
    std::unique_ptr<ceres::CostFunction> cost(
        RelativePoseFactor::Create(T_ab, RandomSqrtInfo<6>(random, 10.0)));
    const PoseBlocks a(T_wa, kAsGiven);
    const PoseBlocks b(T_wb, kAsGiven);
    Eigen::VectorXd r;
    ASSERT_TRUE(EvaluateResidual(*cost, {a.q, a.t, b.q, b.t}, &r));
    EXPECT_LT(r.cwiseAbs().maxCoeff(), kZeroResidualTolerance)
        << "state " << i << ": residual " << r.transpose();
  }
}

TEST(RelativePoseFactor, PureTranslationOffsetInFrameB) {
  // Measured: b is 1 m along a's x axis, turned 90 deg about z.
  const Eigen::Quaterniond q_90z =
      AngleAxis(kPi / 2.0, Eigen::Vector3d::UnitZ());
  const Rigid3d T_ab_measured(q_90z, Eigen::Vector3d(1.0, 0.0, 0.0));
  // Estimate: a unrotated at (2, -1, 0.5); b with the measured rotation but
  // 0.1 m further along ITS OWN x axis, which is the world y axis, so
  // t_wb = (2, -1, 0.5) + (1, 0, 0) + (0, 0.1, 0).
  const Rigid3d T_wa(Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d(2.0, -1.0, 0.5));
  const Rigid3d T_wb(q_90z, Eigen::Vector3d(3.0, -0.9, 0.5));
  // T_ab_meas^-1 T_wa^-1 T_wb = (I, (0.1, 0, 0)), whose log is
  // [rho; omega] = [0.1, 0, 0; 0, 0, 0]; sqrt_info = 1 / 0.01.
  std::unique_ptr<ceres::CostFunction> cost(RelativePoseFactor::Create(
      T_ab_measured, IsotropicPoseSqrtInfo(0.01, 0.01)));
  const PoseBlocks a(T_wa, kAsGiven);
  const PoseBlocks b(T_wb, kAsGiven);
  Eigen::VectorXd r;
  ASSERT_TRUE(EvaluateResidual(*cost, {a.q, a.t, b.q, b.t}, &r));
  Eigen::VectorXd expected(6);
  expected << 10.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), kZeroResidualTolerance)
      << "residual " << r.transpose();
}

TEST(RelativePoseFactor, JacobiansMatchNumericDifferentiation) {
  testing::TestRandom random(102);
  const ceres::EigenQuaternionManifold quaternion_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion_manifold, nullptr, &quaternion_manifold, nullptr};
  GradientCheckRecorder recorder;
  for (const Regime regime :
       {Regime::kGeneric, Regime::kNearIdentity, Regime::kNearPi}) {
    for (int i = 0; i < kGradientStatesPerRegime; ++i) {
      const Rigid3d T_wa = RandomPose(random, 3.0);
      const Rigid3d T_ab_true = RandomPose(random, 1.0);
      const Rigid3d error = RandomError(random, regime);
      // The estimate is off the measurement by `error` (in frame b).
      const Rigid3d T_wb = T_wa * T_ab_true * error;
      std::unique_ptr<ceres::CostFunction> cost(RelativePoseFactor::Create(
          T_ab_true, RandomSqrtInfo<6>(random, 5.0)));
      const PoseBlocks a(T_wa, kAsGiven);
      const PoseBlocks b(T_wb, kAsGiven);
      std::ostringstream state;
      state << RegimeName(regime) << " state " << i;
      recorder.Probe(*cost, manifolds, {a.q, a.t, b.q, b.t}, state.str());
    }
  }
  recorder.ExpectAllPassed(200);
}

// ---------------------------------------------------------------------------
// PosePriorFactor

TEST(PosePriorFactor, ZeroResidualAtThePrior) {
  testing::TestRandom random(201);
  for (int i = 0; i < 50; ++i) {
    const Rigid3d T_prior = RandomPose(random, 3.0);
    std::unique_ptr<ceres::CostFunction> cost(
        PosePriorFactor::Create(T_prior, RandomSqrtInfo<6>(random, 10.0)));
    const PoseBlocks c(T_prior, kAsGiven);
    Eigen::VectorXd r;
    ASSERT_TRUE(EvaluateResidual(*cost, {c.q, c.t}, &r));
    EXPECT_LT(r.cwiseAbs().maxCoeff(), kZeroResidualTolerance)
        << "state " << i << ": residual " << r.transpose();
  }
}

TEST(PosePriorFactor, RotationAboutWorldZAxis) {
  // Prior: camera unrotated at (1, 0, 0). Estimate: the same camera swung by
  // 0.2 rad about the world z axis (through the origin), so it sits at
  // (cos 0.2, sin 0.2, 0) with rotation Rz(0.2).
  const double angle = 0.2;
  const Rigid3d T_prior(Eigen::Quaterniond::Identity(),
                        Eigen::Vector3d(1.0, 0.0, 0.0));
  const Rigid3d T_wc(AngleAxis(angle, Eigen::Vector3d::UnitZ()),
                     Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0));
  // T_prior^-1 T_wc = (Rz(0.2), (cos 0.2 - 1, sin 0.2, 0)): the swing seen
  // from the prior frame, a pure rotation about the z axis through the world
  // origin, which in the prior frame is the point a = (-1, 0, 0). The twist of
  // a rotation omega about an axis through a is rho = -omega x a (the
  // velocity of the frame origin): -(0, 0, 0.2) x (-1, 0, 0) = (0, 0.2, 0).
  // Check against the formula: omega x t = 0.2 (-sin 0.2, cos 0.2 - 1, 0),
  // omega x (omega x t) = -0.04 t, and V^-1 t = t - (omega x t) / 2
  // + C omega x (omega x t) with 0.04 C = 1 - 0.1 cot 0.1 gives
  // x: (cos 0.2 - 1)(0.1 cot 0.1) + 0.1 sin 0.2 = 0,
  // y: sin 0.2 (0.1 cot 0.1) - 0.1 (cos 0.2 - 1) = 0.2 (half-angle identities).
  // So e = [0, 0.2, 0; 0, 0, 0.2] and with sigma_t = 0.05, sigma_r = 0.1 the
  // residual is (0, 4, 0, 0, 0, 2).
  std::unique_ptr<ceres::CostFunction> cost(
      PosePriorFactor::Create(T_prior, IsotropicPoseSqrtInfo(0.05, 0.1)));
  const PoseBlocks c(T_wc, kAsGiven);
  Eigen::VectorXd r;
  ASSERT_TRUE(EvaluateResidual(*cost, {c.q, c.t}, &r));
  Eigen::VectorXd expected(6);
  expected << 0.0, 4.0, 0.0, 0.0, 0.0, 2.0;
  EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), kZeroResidualTolerance)
      << "residual " << r.transpose();
}

TEST(PosePriorFactor, JacobiansMatchNumericDifferentiation) {
  testing::TestRandom random(202);
  const ceres::EigenQuaternionManifold quaternion_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {&quaternion_manifold,
                                                         nullptr};
  GradientCheckRecorder recorder;
  for (const Regime regime :
       {Regime::kGeneric, Regime::kNearIdentity, Regime::kNearPi}) {
    for (int i = 0; i < kGradientStatesPerRegime; ++i) {
      const Rigid3d T_prior = RandomPose(random, 3.0);
      const Rigid3d T_wc = T_prior * RandomError(random, regime);
      std::unique_ptr<ceres::CostFunction> cost(
          PosePriorFactor::Create(T_prior, RandomSqrtInfo<6>(random, 5.0)));
      const PoseBlocks c(T_wc, kAsGiven);
      std::ostringstream state;
      state << RegimeName(regime) << " state " << i;
      recorder.Probe(*cost, manifolds, {c.q, c.t}, state.str());
    }
  }
  recorder.ExpectAllPassed(200);
}

// ---------------------------------------------------------------------------
// ReprojectionFactor

TEST(ReprojectionFactor, ZeroResidualAtTheProjection) {
  testing::TestRandom random(301);
  const PinholeIntrinsics K = TestIntrinsics();
  for (int i = 0; i < 50; ++i) {
    const Rigid3d T_wc = RandomPose(random, 3.0);
    const double depth = random.Uniform(0.5, 10.0);
    const Eigen::Vector3d p_c(depth * random.Uniform(-0.6, 0.6),
                              depth * random.Uniform(-0.45, 0.45),
                              depth);
    const Eigen::Vector3d p_w = T_wc * p_c;
    std::unique_ptr<ceres::CostFunction> cost(ReprojectionFactor::Create(
        K, Project(K, T_wc, p_w), Eigen::Matrix2d::Identity()));
    const PoseBlocks c(T_wc, kAsGiven);
    Eigen::VectorXd r;
    ASSERT_TRUE(EvaluateResidual(*cost, {c.q, c.t, p_w.data()}, &r));
    EXPECT_LT(r.cwiseAbs().maxCoeff(), kZeroResidualTolerance)
        << "state " << i << ": residual " << r.transpose();
  }
}

TEST(ReprojectionFactor, HandComputedPixel) {
  // (0.2, -0.1, 2) from the identity camera: u = 500 * 0.2 / 2 + 320 = 370,
  // v = 500 * (-0.1) / 2 + 240 = 215. Residual = uv - uv_measured.
  const PinholeIntrinsics K = TestIntrinsics();
  const Eigen::Vector3d p_w(0.2, -0.1, 2.0);
  const PoseBlocks identity(Rigid3d::Identity(), kAsGiven);
  {
    std::unique_ptr<ceres::CostFunction> cost(ReprojectionFactor::Create(
        K, Eigen::Vector2d(371.0, 214.0), Eigen::Matrix2d::Identity()));
    Eigen::VectorXd r;
    ASSERT_TRUE(
        EvaluateResidual(*cost, {identity.q, identity.t, p_w.data()}, &r));
    EXPECT_NEAR(r(0), -1.0, kZeroResidualTolerance);
    EXPECT_NEAR(r(1), 1.0, kZeroResidualTolerance);
  }
  {
    // The 2 x 2 sqrt_info multiplies the pixel error:
    // [2 1; 0 0.5] (-1, 1) = (-1, 0.5).
    Eigen::Matrix2d L;
    L << 2.0, 1.0, 0.0, 0.5;
    std::unique_ptr<ceres::CostFunction> cost(
        ReprojectionFactor::Create(K, Eigen::Vector2d(371.0, 214.0), L));
    Eigen::VectorXd r;
    ASSERT_TRUE(
        EvaluateResidual(*cost, {identity.q, identity.t, p_w.data()}, &r));
    EXPECT_NEAR(r(0), -1.0, kZeroResidualTolerance);
    EXPECT_NEAR(r(1), 0.5, kZeroResidualTolerance);
  }
  {
    // The same point in the camera frame, with the camera at (1, 2, 3) turned
    // 90 deg about the world y axis: its z (forward) axis is the world +x,
    // its x axis the world -z, its y axis the world y. So p_c = (0.2, -0.1, 2)
    // is p_w = (1, 2, 3) + 2 x_w - 0.1 y_w - 0.2 z_w = (3, 1.9, 2.8).
    const PoseBlocks turned(
        Rigid3d(AngleAxis(kPi / 2.0, Eigen::Vector3d::UnitY()),
                Eigen::Vector3d(1.0, 2.0, 3.0)),
        kAsGiven);
    const Eigen::Vector3d p_w_turned(3.0, 1.9, 2.8);
    std::unique_ptr<ceres::CostFunction> cost(ReprojectionFactor::Create(
        K, Eigen::Vector2d(371.0, 214.0), Eigen::Matrix2d::Identity()));
    Eigen::VectorXd r;
    ASSERT_TRUE(
        EvaluateResidual(*cost, {turned.q, turned.t, p_w_turned.data()}, &r));
    EXPECT_NEAR(r(0), -1.0, kZeroResidualTolerance);
    EXPECT_NEAR(r(1), 1.0, kZeroResidualTolerance);
  }
}

TEST(ReprojectionFactor, FailsForPointsAtOrBehindTheCamera) {
  const PinholeIntrinsics K = TestIntrinsics();
  std::unique_ptr<ceres::CostFunction> cost(ReprojectionFactor::Create(
      K, Eigen::Vector2d(320.0, 240.0), Eigen::Matrix2d::Identity()));
  const PoseBlocks identity(Rigid3d::Identity(), kAsGiven);
  Eigen::VectorXd r;
  for (const Eigen::Vector3d& p_w : {Eigen::Vector3d(0.2, -0.1, -2.0),
                                     Eigen::Vector3d(0.0, 0.0, -1e-3),
                                     Eigen::Vector3d(0.3, 0.1, 0.0)}) {
    const std::vector<const double*> parameters = {
        identity.q, identity.t, p_w.data()};
    EXPECT_FALSE(EvaluateResidual(*cost, parameters, &r))
        << "point " << p_w.transpose();
    EXPECT_FALSE(EvaluateWithJacobians(*cost, parameters))
        << "point " << p_w.transpose();
  }
  // A camera looking down the world -z axis (turned pi about y) has the
  // point (0, 0, 5) behind it and (0, 0, -5) in front.
  const PoseBlocks flipped(Rigid3d(AngleAxis(kPi, Eigen::Vector3d::UnitY()),
                                   Eigen::Vector3d::Zero()),
                           kAsGiven);
  const Eigen::Vector3d behind(0.0, 0.0, 5.0);
  const Eigen::Vector3d in_front(0.0, 0.0, -5.0);
  EXPECT_FALSE(
      EvaluateResidual(*cost, {flipped.q, flipped.t, behind.data()}, &r));
  EXPECT_FALSE(
      EvaluateWithJacobians(*cost, {flipped.q, flipped.t, behind.data()}));
  EXPECT_TRUE(
      EvaluateResidual(*cost, {flipped.q, flipped.t, in_front.data()}, &r));
  EXPECT_TRUE(
      EvaluateWithJacobians(*cost, {flipped.q, flipped.t, in_front.data()}));
}

TEST(ReprojectionFactor, JacobiansMatchNumericDifferentiation) {
  testing::TestRandom random(302);
  PinholeIntrinsics K;
  K.fx = 520.0;
  K.fy = 480.0;
  K.cx = 315.0;
  K.cy = 245.0;
  const ceres::EigenQuaternionManifold quaternion_manifold;
  const std::vector<const ceres::Manifold*> manifolds = {
      &quaternion_manifold, nullptr, nullptr};
  GradientCheckRecorder recorder;
  for (int i = 0; i < kReprojectionGradientStates; ++i) {
    const Rigid3d T_wc = RandomPose(random, 3.0);
    const double depth = random.Uniform(0.5, 10.0);
    const Eigen::Vector3d p_c(depth * random.Uniform(-0.7, 0.7),
                              depth * random.Uniform(-0.5, 0.5),
                              depth);
    const Eigen::Vector3d p_w = T_wc * p_c;
    const Eigen::Vector2d uv_measured =
        Project(K, T_wc, p_w) +
        Eigen::Vector2d(random.Normal(3.0), random.Normal(3.0));
    std::unique_ptr<ceres::CostFunction> cost(ReprojectionFactor::Create(
        K, uv_measured, RandomSqrtInfo<2>(random, 1.0)));
    const PoseBlocks c(T_wc, kAsGiven);
    std::ostringstream state;
    state << "state " << i << " (depth " << depth << ")";
    recorder.Probe(*cost, manifolds, {c.q, c.t, p_w.data()}, state.str());
  }
  recorder.ExpectAllPassed(200);
}

// ---------------------------------------------------------------------------
// Small solves

ceres::Solver::Options TightSolverOptions() {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.num_threads = 1;
  return options;
}

TEST(CameraFactorSolve, PoseChainWithPriorConvergesToTruth) {
  testing::TestRandom random(401);
  constexpr int kPoses = 5;
  std::vector<Rigid3d> truth;
  for (int i = 0; i < kPoses; ++i) {
    // On a line along world x, each camera turned a little differently.
    truth.emplace_back(
        AngleAxis(0.1 * i + 0.05, Eigen::Vector3d(0.2, 1.0, 0.1)),
        Eigen::Vector3d(1.0 * i, 0.0, 0.0));
  }
  std::vector<PoseBlocks> poses;
  for (const Rigid3d& T : truth) {
    // Start 0.1-0.3 rad and ~0.2 m off.
    const Rigid3d perturbation(random.RotationOfAngle(random.Uniform(0.1, 0.3)),
                               random.NormalVector(0.2));
    poses.emplace_back(T * perturbation, kAsGiven);
  }

  ceres::Problem problem;
  for (PoseBlocks& pose : poses) {
    problem.AddParameterBlock(pose.q, 4, new ceres::EigenQuaternionManifold);
    problem.AddParameterBlock(pose.t, 3);
  }
  problem.AddResidualBlock(
      PosePriorFactor::Create(truth[0], IsotropicPoseSqrtInfo(0.01, 0.01)),
      nullptr,
      poses[0].q,
      poses[0].t);
  for (int i = 0; i + 1 < kPoses; ++i) {
    problem.AddResidualBlock(
        RelativePoseFactor::Create(truth[i].Inverse() * truth[i + 1],
                                   IsotropicPoseSqrtInfo(0.05, 0.02)),
        nullptr,
        poses[i].q,
        poses[i].t,
        poses[i + 1].q,
        poses[i + 1].t);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(TightSolverOptions(), &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();

  for (int i = 0; i < kPoses; ++i) {
    const Rigid3d estimate = poses[i].ToRigid();
    EXPECT_LT(AngleBetween(estimate.q.normalized(), truth[i].q), 1e-6)
        << "pose " << i << "\n"
        << summary.BriefReport();
    EXPECT_LT((estimate.t - truth[i].t).norm(), 1e-6) << "pose " << i << "\n"
                                                      << summary.BriefReport();
  }
}

TEST(CameraFactorSolve, BundleAdjustmentWithFixedCamerasRecoversPoints) {
  testing::TestRandom random(402);
  const PinholeIntrinsics K = TestIntrinsics();
  // Three cameras on a baseline, all looking roughly along +z at the scene.
  const std::vector<Rigid3d> cameras = {
      Rigid3d(AngleAxis(0.15, Eigen::Vector3d::UnitY()),
              Eigen::Vector3d(-1.0, 0.0, 0.0)),
      Rigid3d(AngleAxis(0.05, Eigen::Vector3d::UnitX()),
              Eigen::Vector3d(0.0, -0.3, 0.0)),
      Rigid3d(AngleAxis(-0.15, Eigen::Vector3d(0.1, 1.0, 0.0)),
              Eigen::Vector3d(1.0, 0.2, 0.1))};
  constexpr int kPoints = 10;
  std::vector<Eigen::Vector3d> points_true;
  std::vector<Eigen::Vector3d> points;
  for (int j = 0; j < kPoints; ++j) {
    points_true.emplace_back(random.Uniform(-1.5, 1.5),
                             random.Uniform(-1.0, 1.0),
                             random.Uniform(4.0, 7.0));
    points.push_back(points_true.back() + 0.05 * random.UnitVector());
  }

  std::vector<PoseBlocks> camera_blocks;
  for (const Rigid3d& T : cameras) camera_blocks.emplace_back(T, kAsGiven);
  ceres::Problem problem;
  for (PoseBlocks& camera : camera_blocks) {
    problem.AddParameterBlock(camera.q, 4, new ceres::EigenQuaternionManifold);
    problem.AddParameterBlock(camera.t, 3);
    problem.SetParameterBlockConstant(camera.q);
    problem.SetParameterBlockConstant(camera.t);
  }
  for (int j = 0; j < kPoints; ++j) {
    for (size_t c = 0; c < cameras.size(); ++c) {
      problem.AddResidualBlock(
          ReprojectionFactor::Create(K,
                                     Project(K, cameras[c], points_true[j]),
                                     Eigen::Matrix2d::Identity()),
          nullptr,
          camera_blocks[c].q,
          camera_blocks[c].t,
          points[j].data());
    }
  }
  ceres::Solver::Summary summary;
  ceres::Solve(TightSolverOptions(), &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();

  for (int j = 0; j < kPoints; ++j) {
    EXPECT_LT((points[j] - points_true[j]).norm(), 1e-6)
        << "point " << j << ": " << points[j].transpose() << " vs "
        << points_true[j].transpose() << "\n"
        << summary.BriefReport();
  }
  // The cameras were held fixed.
  for (size_t c = 0; c < cameras.size(); ++c) {
    const Rigid3d camera = camera_blocks[c].ToRigid();
    EXPECT_EQ(camera.q.coeffs(), cameras[c].q.coeffs());
    EXPECT_EQ(camera.t, cameras[c].t);
  }
}

}  // namespace
}  // namespace symba
