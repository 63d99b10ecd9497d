// Small solves: known cameras observe one object through multi-hypothesis
// detections; the object edges must recover the object within the noise.
// Cameras: 8 on a circle of radius 2.5 m around the object, 1.2 m above it,
// looking at it; held constant. Hypothesis noise: 1 cm and 1 deg per axis
// (Gaussian), information matching it.
//
// Tolerance: a max-mixture edge follows its nearest hypothesis rather than
// the mean of its hypotheses, so each edge carries about one hypothesis'
// noise. The sparsest-seen quantity (a 4-fold mode, seen in 4 of 8 views)
// then has a per-axis sigma of about 1 / sqrt(4) = 0.5 deg, and the norm of
// a 3-D error 3 sigma out is about 3 * 0.5 * sqrt(3) = 2.6 deg; likewise
// 2.6 cm. The tests allow 3 deg and 3 cm.
#include <cmath>
#include <memory>
#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "factors/factor_test_util.h"
#include "symba/factors/asymmetric_object_edge.h"
#include "symba/factors/continuous_object_edge.h"
#include "symba/factors/discrete_object_edge.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/manifolds/axis_manifold.h"
#include "test_support/random.h"

namespace symba {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kSigmaT = 0.01;
constexpr double kSigmaR = 1.0 * kDeg;
constexpr double kToleranceT = 0.03;
constexpr double kToleranceR = 3.0 * kDeg;

// Camera pose at `eye` looking at `target` (z forward, y down, world z up).
Rigid3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  return Rigid3d(Eigen::Quaterniond(R), eye);
}

std::vector<Rigid3d> CamerasAround(const Eigen::Vector3d& target) {
  std::vector<Rigid3d> cameras;
  for (int i = 0; i < 8; ++i) {
    const double angle = 2.0 * kPi * i / 8.0;
    const Eigen::Vector3d eye =
        target +
        Eigen::Vector3d(2.5 * std::cos(angle), 2.5 * std::sin(angle), 1.2);
    cameras.push_back(LookAt(eye, target));
  }
  return cameras;
}

Rigid3d Noise(testing::TestRandom& random) {
  return Rigid3d(ExpSO3(random.NormalVector(kSigmaR)),
                 random.NormalVector(kSigmaT));
}

double RotationError(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

ceres::Solver::Summary Solve(ceres::Problem* problem) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 100;
  ceres::Solver::Summary summary;
  ceres::Solve(options, problem, &summary);
  return summary;
}

TEST(ObjectRecoveryTest, AsymmetricObjectFullPose) {
  testing::TestRandom random(41);
  const Rigid3d T_wo_true(random.Rotation(), Eigen::Vector3d(0.3, -0.2, 0.5));
  const std::vector<Rigid3d> cameras = CamerasAround(T_wo_true.t);
  std::vector<testing::PoseBlocks> camera_blocks(cameras.begin(),
                                                 cameras.end());
  // Start 10 cm and 10 deg off.
  testing::PoseBlocks object(
      Rigid3d(T_wo_true.q * ExpSO3(Eigen::Vector3d(0.1, -0.1, 0.1)),
              T_wo_true.t + Eigen::Vector3d(0.06, -0.06, 0.05)));
  ceres::Problem problem;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Rigid3d T_co = cameras[i].Inverse() * T_wo_true;
    std::vector<PoseComponent> components;
    for (int j = 0; j < 8; ++j) {
      components.push_back(
          {T_co * Noise(random), IsotropicPoseSqrtInfo(kSigmaT, kSigmaR), 1.0});
    }
    for (int j = 0; j < 2; ++j) {  // outliers: random orientation
      components.push_back(
          {Rigid3d(random.Rotation(), T_co.t + random.NormalVector(0.3)),
           IsotropicPoseSqrtInfo(kSigmaT, kSigmaR),
           1.0});
    }
    std::unique_ptr<AsymmetricObjectEdge> edge;
    ASSERT_TRUE(
        CreateAsymmetricObjectEdge(components, MixtureOptions(), &edge).ok());
    problem.AddResidualBlock(edge.release(),
                             nullptr,
                             camera_blocks[i].q,
                             camera_blocks[i].t,
                             object.q,
                             object.t);
    problem.SetManifold(camera_blocks[i].q, new ceres::EigenQuaternionManifold);
    problem.SetParameterBlockConstant(camera_blocks[i].q);
    problem.SetParameterBlockConstant(camera_blocks[i].t);
  }
  problem.SetManifold(object.q, new ceres::EigenQuaternionManifold);
  const ceres::Solver::Summary summary = Solve(&problem);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  const Rigid3d T_wo = object.ToRigid();
  EXPECT_LT((T_wo.t - T_wo_true.t).norm(), kToleranceT);
  EXPECT_LT(RotationError(T_wo.q, T_wo_true.q), kToleranceR);
}

// Solves for an asymmetric object seen by the 8 cameras, plus one wrong
// detection 0.5 m off (e.g. a mis-association) whose edge gets `wrong_loss`.
// Returns the position error.
double AsymmetricPositionErrorWithWrongDetection(
    ceres::LossFunction* wrong_loss) {
  testing::TestRandom random(48);
  const Rigid3d T_wo_true(random.Rotation(), Eigen::Vector3d(0.3, -0.2, 0.5));
  const std::vector<Rigid3d> cameras = CamerasAround(T_wo_true.t);
  std::vector<testing::PoseBlocks> camera_blocks(cameras.begin(),
                                                 cameras.end());
  testing::PoseBlocks object(T_wo_true);
  ceres::Problem problem;
  for (size_t i = 0; i <= cameras.size(); ++i) {
    const size_t camera = i % cameras.size();
    const bool wrong = i == cameras.size();
    const Rigid3d T_wo_seen =
        wrong ? Rigid3d(T_wo_true.q, T_wo_true.t + Eigen::Vector3d(0.5, 0, 0))
              : T_wo_true;
    const Rigid3d T_co = cameras[camera].Inverse() * T_wo_seen;
    std::vector<PoseComponent> components;
    for (int j = 0; j < 4; ++j) {
      components.push_back(
          {T_co * Noise(random), IsotropicPoseSqrtInfo(kSigmaT, kSigmaR), 1.0});
    }
    std::unique_ptr<AsymmetricObjectEdge> edge;
    EXPECT_TRUE(
        CreateAsymmetricObjectEdge(components, MixtureOptions(), &edge).ok());
    problem.AddResidualBlock(edge.release(),
                             wrong ? wrong_loss : nullptr,
                             camera_blocks[camera].q,
                             camera_blocks[camera].t,
                             object.q,
                             object.t);
  }
  for (auto& block : camera_blocks) {
    problem.SetManifold(block.q, new ceres::EigenQuaternionManifold);
    problem.SetParameterBlockConstant(block.q);
    problem.SetParameterBlockConstant(block.t);
  }
  problem.SetManifold(object.q, new ceres::EigenQuaternionManifold);
  const ceres::Solver::Summary summary = Solve(&problem);
  EXPECT_TRUE(summary.IsSolutionUsable());
  return (object.ToRigid().t - T_wo_true.t).norm();
}

TEST(ObjectRecoveryTest, RobustLossOnAnObjectEdgeBoundsAWrongDetection) {
  // Without a loss the wrong edge pulls the object by about 0.5 m / 9.
  EXPECT_GT(AsymmetricPositionErrorWithWrongDetection(nullptr), kToleranceT);
  // A Cauchy loss (scale 1 in whitened units) makes its pull negligible.
  EXPECT_LT(
      AsymmetricPositionErrorWithWrongDetection(new ceres::CauchyLoss(1.0)),
      kToleranceT);
}

// A k-fold object about an arbitrary object-frame axis. Camera i sees modes
// i and i + 1 (mod k) only, as a view of a table may show part of its modes.
void RecoverDiscreteObject(int order,
                           const Eigen::Vector3d& a_o,
                           const Eigen::Quaterniond& q_wo_true,
                           unsigned seed) {
  testing::TestRandom random(seed);
  const Rigid3d T_wo_true(q_wo_true, Eigen::Vector3d(-0.4, 0.2, 0.4));
  const std::vector<Rigid3d> cameras = CamerasAround(T_wo_true.t);
  std::vector<testing::PoseBlocks> camera_blocks(cameras.begin(),
                                                 cameras.end());

  // Map object initialised from a perturbed first detection.
  const Eigen::Quaterniond q_init =
      q_wo_true * ExpSO3(Eigen::Vector3d(0.05, 0.08, -0.06));
  const SymmetryAnchor anchor = SymmetryAnchor::FromObjectRotation(q_init, a_o);
  double t_wo[3] = {
      T_wo_true.t.x() + 0.07, T_wo_true.t.y() - 0.05, T_wo_true.t.z() + 0.04};
  double a_w[3] = {anchor.a_w0.x(), anchor.a_w0.y(), anchor.a_w0.z()};
  std::vector<double> theta(order);
  for (int m = 0; m < order; ++m) theta[m] = 2.0 * kPi * m / order + 0.1;

  ceres::Problem problem;
  for (size_t i = 0; i < cameras.size(); ++i) {
    problem.AddParameterBlock(
        camera_blocks[i].q, 4, new ceres::EigenQuaternionManifold);
    for (int view = 0; view < std::min(order, 2); ++view) {
      const int m = (static_cast<int>(i) + view) % order;
      const Rigid3d T_wo_m(q_wo_true * Eigen::Quaterniond(Eigen::AngleAxisd(
                                           2.0 * kPi * m / order, a_o)),
                           T_wo_true.t);
      const Rigid3d T_co = cameras[i].Inverse() * T_wo_m;
      std::vector<PoseComponent> components;
      for (int j = 0; j < 6; ++j) {
        components.push_back({T_co * Noise(random),
                              IsotropicPoseSqrtInfo(kSigmaT, kSigmaR),
                              1.0});
      }
      std::unique_ptr<DiscreteObjectEdge> edge;
      ASSERT_TRUE(
          CreateDiscreteObjectEdge(components, anchor, MixtureOptions(), &edge)
              .ok());
      problem.AddResidualBlock(edge.release(),
                               nullptr,
                               camera_blocks[i].q,
                               camera_blocks[i].t,
                               t_wo,
                               a_w,
                               &theta[m]);
    }
    problem.SetParameterBlockConstant(camera_blocks[i].q);
    problem.SetParameterBlockConstant(camera_blocks[i].t);
  }
  problem.SetManifold(a_w, new AxisManifold);
  const ceres::Solver::Summary summary = Solve(&problem);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();

  const Eigen::Vector3d a_w_est(a_w[0], a_w[1], a_w[2]);
  EXPECT_LT((Eigen::Vector3d(t_wo[0], t_wo[1], t_wo[2]) - T_wo_true.t).norm(),
            kToleranceT);
  EXPECT_LT(std::acos(std::min(1.0, a_w_est.dot(q_wo_true * a_o))),
            kToleranceR);
  for (int m = 0; m < order; ++m) {
    const Eigen::Quaterniond expected =
        q_wo_true *
        Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * kPi * m / order, a_o));
    EXPECT_LT(RotationError(SymmetricObjectRotation(anchor, a_w_est, theta[m]),
                            expected),
              kToleranceR)
        << "mode " << m << " of " << order;
  }
}

TEST(ObjectRecoveryTest, TwoFoldTableWithVerticalAxis) {
  // An upright table: object z is the symmetry axis and points up.
  RecoverDiscreteObject(
      2,
      Eigen::Vector3d::UnitZ(),
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())),
      42);
}

TEST(ObjectRecoveryTest, FourFoldObjectWithTiltedNonZAxis) {
  testing::TestRandom random(43);
  RecoverDiscreteObject(4, random.UnitVector(), random.Rotation(), 44);
}

TEST(ObjectRecoveryTest, TwoFoldObjectWithArbitraryAxis) {
  testing::TestRandom random(45);
  RecoverDiscreteObject(2, random.UnitVector(), random.Rotation(), 46);
}

TEST(ObjectRecoveryTest, ContinuousObjectPositionAndAxis) {
  testing::TestRandom random(47);
  const Eigen::Vector3d t_wo_true(0.1, 0.4, 0.3);
  const Eigen::Vector3d a_w_true =
      Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()) *
      Eigen::Vector3d::UnitZ();
  const std::vector<Rigid3d> cameras = CamerasAround(t_wo_true);
  std::vector<testing::PoseBlocks> camera_blocks(cameras.begin(),
                                                 cameras.end());
  double t_wo[3] = {
      t_wo_true.x() - 0.08, t_wo_true.y() + 0.06, t_wo_true.z() + 0.05};
  double a_w[3] = {0.0, 0.0, 1.0};  // start at the pole, 0.2 rad off

  ceres::Problem problem;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Eigen::Vector3d t_co = cameras[i].Inverse() * t_wo_true;
    std::vector<TranslationComponent> components;
    for (int j = 0; j < 10; ++j) {
      components.push_back({t_co + random.NormalVector(kSigmaT),
                            Eigen::Matrix3d::Identity() / kSigmaT,
                            1.0});
    }
    AxisMeasurement axis;
    axis.a_c = ExpSO3(random.NormalVector(kSigmaR)) *
               (cameras[i].q.conjugate() * a_w_true);
    axis.sqrt_info = Eigen::Matrix2d::Identity() / kSigmaR;
    axis.gamma = 1.0;
    std::unique_ptr<ContinuousObjectEdge> edge;
    ASSERT_TRUE(
        CreateContinuousObjectEdge(components, axis, MixtureOptions(), &edge)
            .ok());
    problem.AddResidualBlock(edge.release(),
                             nullptr,
                             camera_blocks[i].q,
                             camera_blocks[i].t,
                             t_wo,
                             a_w);
    problem.SetManifold(camera_blocks[i].q, new ceres::EigenQuaternionManifold);
    problem.SetParameterBlockConstant(camera_blocks[i].q);
    problem.SetParameterBlockConstant(camera_blocks[i].t);
  }
  problem.SetManifold(a_w, new AxisManifold);
  const ceres::Solver::Summary summary = Solve(&problem);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_LT((Eigen::Vector3d(t_wo[0], t_wo[1], t_wo[2]) - t_wo_true).norm(),
            kToleranceT);
  EXPECT_LT(std::acos(std::min(
                1.0, Eigen::Vector3d(a_w[0], a_w[1], a_w[2]).dot(a_w_true))),
            kToleranceR);
}

}  // namespace
}  // namespace symba
